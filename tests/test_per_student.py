"""Per-student surfaces (issue 32, item 3): ``release --per-student`` gives every student of the roster a variant of
notebook 05's surface, ``lab.my_surface`` and the check give the student theirs, and the grader grades the numbers a
student reports against the exact values of the student's own variant and names the owner of a classmate's numbers.

Module-scoped set-ups: the variants of a class of 40 with the exact numbers of each (``klass``), a per-student hand-out
of five (``handout``), and one folder of six submissions graded in the sandbox (``graded``)."""

import csv
import io
import itertools
import json
import os
import shutil
from pathlib import Path

import nbformat
import numpy as np
import pytest

from lab.geometry import analytic
from lab.teaching.course import grade, release
from lab.teaching.course import variants as course_variants
from lab.teaching.grader import assignments, notebook
from lab.teaching.kernel import variants
from lab.teaching.tasks import TASKS
from lab.teaching.untrusted import reported_outcome

ROOT = Path(__file__).resolve().parent.parent
ID = "05_visualize_curvature"
SOLUTION = ROOT / "solutions" / "en" / f"{ID}.ipynb"
ROSTER = [f"student{k:02d}" for k in range(40)]
SECRET = b"a course secret for the tests 5f0c2d9e41"
CLASS = ["ada", "bea", "cy", "dan", "eve"]  # the hand-out's roster (the graded folder adds zed, not on it)
TASK = TASKS["own_surface"]

pytestmark = pytest.mark.xdist_group("per_student")  # one class, one hand-out, one graded folder for the module


def printed(numbers):
    """The numbers as the notebook's cell prints them (ten significant digits), read back."""
    return np.array([float(f"{x:.10g}") for x in numbers])


@pytest.fixture(scope="module")
def klass():
    """The variants of a class of 40 under SECRET, and the exact numbers (K min, K max, H min, H max) of each."""
    table = course_variants.build(ROSTER, SECRET)
    numbers = {s: TASK.expected(TASK.variant_cases(s, table[s][ID])[0]) for s in ROSTER}
    return {"table": table, "numbers": numbers, "common": TASK.expected(TASK.variant_cases(None, None)[0])}


@pytest.fixture(scope="module")
def handout(tmp_path_factory):
    """A per-student hand-out for CLASS, and its table."""
    out = release.release(tmp_path_factory.mktemp("handout") / "out", per_student=(CLASS, SECRET))
    return {"out": out, "table": variants.read_table(out / variants.TABLE)}


def _notebook(numbers, dst, answer=None):
    """The English solution of 05 whose answer cell reports ``numbers`` (or holds ``answer``'s code)."""
    nb = nbformat.read(SOLUTION, as_version=4)
    cell = next(c for c in nb.cells if "check.own_surface(answer)" in c.source)
    line = answer or f"answer = ({', '.join(f'{x:.10g}' for x in numbers)})"
    cell.source = f"{line}\ncheck.own_surface(answer)"
    dst.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, dst)
    return dst


@pytest.fixture(scope="module")
def graded(handout, tmp_path_factory):
    """Six submissions graded with the hand-out's table: ada and bea their own numbers; cy hands in ada's notebook;
    dan reports bea's numbers; eve computes her answer by code; zed (not on the roster) the common surface's."""
    table, root = handout["table"], tmp_path_factory.mktemp("graded")
    subs = root / "subs"
    own = {s: TASK.expected(TASK.variant_cases(s, table.params(s, ID))[0]) for s in CLASS}
    _notebook(own["ada"], subs / "ada" / f"{ID}.ipynb")
    _notebook(own["bea"], subs / "bea" / f"{ID}.ipynb")
    (subs / "cy").mkdir()
    shutil.copy(subs / "ada" / f"{ID}.ipynb", subs / "cy" / f"{ID}.ipynb")
    _notebook(own["bea"], subs / "dan" / f"{ID}.ipynb")
    _notebook(None, subs / "eve" / f"{ID}.ipynb", "answer = (K.min(), K.max(), H.min(), H.max())")
    _notebook(TASK.expected(TASK.variant_cases(None, None)[0]), subs / "zed" / f"{ID}.ipynb")
    results = grade.grade_folder(subs, root / "reports", jobs=2, seed=32, timeout=120,
                                 variants=handout["out"] / variants.TABLE)
    return {"results": {r.student: r for r in results}, "reports": root / "reports", "own": own, "table": table.id}


def own_surface(result):
    return next(t for t in result.tasks if t["task"] == "own_surface")


# -- the variants of a class of 40 -------------------------------------------------------------------------------


def test_forty_students_get_forty_different_surfaces_and_numbers(klass):
    table, numbers = klass["table"], klass["numbers"]
    assert sorted(table) == ROSTER and all(set(v) == {ID} for v in table.values())
    params = [tuple(sorted(table[s][ID].items())) for s in ROSTER]
    assert len(set(params)) == 40
    nets = [variants.PRACTICAL.surface(table[s][ID]).control_points for s in ROSTER]
    assert all(not np.array_equal(a, b) for a, b in itertools.combinations(nets, 2))
    # pairwise, the reported numbers differ far beyond the judge's tolerance (1e-8 relative): at least 1e-4
    closest = min(np.max(np.abs(numbers[a] - numbers[b]) / np.abs(numbers[b])) for a, b in itertools.permutations(ROSTER, 2))
    assert closest > 1e-4, closest
    spread = np.array([numbers[s] for s in ROSTER])
    print("\n40 variants: K min", spread[:, 0].min(), "…", spread[:, 0].max(), "| K max", spread[:, 1].min(), "…",
          spread[:, 1].max(), "| H min", spread[:, 2].min(), "…", spread[:, 2].max(), "| H max", spread[:, 3].min(),
          "…", spread[:, 3].max(), "| closest pair (relative):", closest)
    assert not any(np.allclose(numbers[s], klass["common"], rtol=1e-6) for s in ROSTER)  # nobody has the common one


def test_every_variant_keeps_the_character_of_the_common_surface(klass):
    """Equal difficulty: the same patches; the sign of K at every corner of depth 1 (the library's exact curvature
    everywhere, and rational arithmetic at the corners nearest to K = 0) and at the bump's top as on the common
    surface; no degenerate corner; the normal points down (the practical's orientation)."""
    def corners(params):
        patches = variants.PRACTICAL.surface(params).to_bezier_patches().refine(1)
        return patches, patches.corner_curvature()

    def top(values):  # the corners (a point shared by patches is one corner of each) that hold the largest value
        return set(np.flatnonzero(values >= np.max(values) * (1 - 1e-9)))

    common_patches, common = corners(None)
    nearest = np.argsort(np.abs(common.K), axis=None)[:4]
    for student in ROSTER:
        patches, c = corners(klass["table"][student][ID])
        assert patches.control_points.shape == common_patches.control_points.shape
        assert np.array_equal(np.sign(c.K), np.sign(common.K)), student
        assert not np.any(c.degenerate), student
        for mine, theirs in ((c.K, common.K), (c.H, common.H)):  # the bump's top: the largest K and H, as before
            assert top(mine) & top(theirs), student
        for flat in nearest:
            p, a, b = np.unravel_index(flat, c.K.shape)
            K = analytic.to_float(analytic.bezier_curvature_exact(patches.control_points[p], a, b)).K
            assert np.sign(K) == np.sign(common.K[p, a, b]) != 0, (student, p, a, b)
        P = patches.control_points  # b_u × b_v at each patch's corner (0, 0) points down
        assert np.all(np.cross(P[:, 1, 0] - P[:, 0, 0], P[:, 0, 1] - P[:, 0, 0])[:, 2] < 0), student


def test_the_variants_are_deterministic_and_come_from_the_secret(klass):
    assert course_variants.build(list(reversed(ROSTER)), SECRET) == klass["table"]
    other = course_variants.build(ROSTER, SECRET + b"!")
    assert all(other[s] != klass["table"][s] for s in ROSTER)
    later = course_variants.build([*ROSTER, "zz-latecomer"], SECRET)  # a student added later changes nobody else's
    assert {s: later[s] for s in ROSTER} == klass["table"]
    with pytest.raises(course_variants.VariantError, match="at least 16 bytes"):
        course_variants.read_secret(_file(Path(os.environ.get("TMPDIR", "/tmp")) / "short-secret", b"12345678\n"))
    with pytest.raises(course_variants.VariantError, match="no user name"):
        course_variants.build(["ada", "../etc"], SECRET)


def _file(path, data):
    path.write_bytes(data)
    return path


def test_each_variant_passes_with_its_own_numbers_and_fails_with_a_classmates(klass, tmp_path):
    """All 40 × 40 on the reference computation: a variant's printed numbers pass for it and for no other, and the
    grader names the owner of a classmate's numbers."""
    table, numbers = klass["table"], klass["numbers"]
    cases = {s: TASK.variant_cases(s, table[s][ID])[0] for s in ROSTER}
    for s, c in itertools.product(ROSTER, ROSTER):
        passed = TASK.judge(cases[s], printed(numbers[c]), numbers[s])[0]
        assert passed == (s == c), (s, c)
    found = assignments.load(ROOT / "exercises" / "en" / f"{ID}.ipynb")
    table_file = tmp_path / "variants.json"
    course_variants.write_table(table_file, table)
    prepared = notebook.Prepared(found, 1, tmp_path / "pkg", variants.read_table(table_file))
    k = [name for name, _obj, _points in prepared.tasks].index("own_surface")
    assert prepared.tasks[k] == ("own_surface", "answer", 2.0) and found.max_score == 10  # 2 points per student
    for s, c in zip(ROSTER, ROSTER[1:] + ROSTER[:1]):
        view = prepared.for_student(s)
        assert view.cases[k][0].info["params"] == table[s][ID]
        assert view.owners(k, printed(numbers[c])) == [c]
        assert view.owners(k, printed(numbers[s])) == []  # one's own numbers are nobody else's
    # the wrong answers a student gives name their mistake, for any variant
    s = ROSTER[3]
    exp = numbers[s]
    for value, key in ((klass["common"], "common_surface"), (exp[[2, 3, 0, 1]], "order"),
                       (np.array([exp[0], exp[1], -exp[3], -exp[2]]), "orientation"), (exp * (1 + 1e-6), "digits")):
        passed, _exp, _got, hint = TASK.judge(cases[s], printed(value), exp)
        assert not passed and getattr(hint, "key", "") == key, (key, hint)


def test_reported_numbers_are_read_as_written_never_run():
    ok = reported_outcome(["answer = 1", "x = 2\nanswer = (1.5, -2e-3,\n          3, 4)  # mine"], "answer")
    assert ok == {"status": "ok", "value": {"kind": "array", "shape": [4], "data": [1.5, -0.002, 3.0, 4.0]}}
    code = reported_outcome(["answer = (K.min(), K.max(), H.min(), H.max())"], "answer")
    assert code["status"] == "error" and "not numbers as written" in code["message"]
    for sources in (["    answer = (1, 2)", "answer2 = 3", "answer == 3"], []):  # indented, another name, a comparison
        assert reported_outcome(sources, "answer")["status"] == "not implemented"
    hostile = reported_outcome(["answer = " + "(" * 100_000], "answer")
    assert hostile["status"] == "error" and len(hostile["message"]) < 400
    assert reported_outcome(["answer = (True, 2)"], "answer")["status"] == "error"  # booleans are no numbers


# -- the hand-out ------------------------------------------------------------------------------------------------


def test_the_hand_out_carries_the_table_and_never_the_secret(handout):
    out, table = handout["out"], handout["table"]
    assert table.students == course_variants.build(CLASS, SECRET)
    data = json.loads((out / variants.TABLE).read_text())
    assert data["id"] == table.id and data["format"] == variants.FORMAT
    for lang in ("en", "de"):
        lab_meta = nbformat.read(out / "exercises" / lang / f"{ID}.ipynb", as_version=4).metadata["lab"]
        assert lab_meta["variants"] == table.id
        assert "variants" not in nbformat.read(out / "exercises" / lang / "04_color_maps.ipynb",
                                               as_version=4).metadata["lab"]
    assert json.loads((out / release.MARK).read_text())["variants"] == table.id
    assert 'lab.my_surface("05_visualize_curvature")' in (out / "README.md").read_text()
    files = [p for p in out.rglob("*") if p.is_file()]
    assert len(files) > 100 and not [p for p in files if SECRET in p.read_bytes() or SECRET.hex().encode()
                                     in p.read_bytes()]
    assert release.secret_in(out, SECRET) == []
    (out / "exercises" / "leak.txt").write_bytes(b"oops " + SECRET)  # the release's own search finds a leak
    try:
        assert release.secret_in(out, SECRET) == [out / "exercises" / "leak.txt"]
    finally:
        (out / "exercises" / "leak.txt").unlink()


def test_my_surface_and_the_check_in_a_kernel_give_the_students_own_variant(handout):
    """A kernel of bea's JupyterLab (JUPYTERHUB_USER), working in the hand-out: her surface, her check; then one of a
    user not on the roster: the common surface, said so."""
    from jupyter_client.manager import KernelManager

    table = handout["table"]
    bea, ada = (TASK.expected(TASK.variant_cases(s, table.params(s, ID))[0]) for s in ("bea", "ada"))
    km = KernelManager(kernel_name="python3")
    km.start_kernel(cwd=str(handout["out"] / "exercises" / "en"), env={**os.environ, "JUPYTERHUB_USER": "bea"},
                    extra_arguments=["--IPKernelApp.log_level=ERROR"])
    kc = km.client()
    kc.start_channels()
    try:
        kc.wait_for_ready(timeout=120)

        def run(code):
            out = []
            reply = kc.execute_interactive(code, timeout=300, output_hook=lambda m: out.append(
                m["content"].get("text", "") if m["msg_type"] == "stream" else ""))
            assert reply["content"]["status"] == "ok", reply["content"]
            return "".join(out)

        shown = run("import json, lab\nfrom lab import check\nsurface = lab.my_surface('05_visualize_curvature')\n"
                    "print(surface.variant.status, surface.variant.student)\n"
                    "print(json.dumps(surface.control_points.tolist()))\nprint(surface.variant)")
        status, net, text = shown.splitlines()[:3]
        assert status == "own bea" and "the variant of bea" in text
        mine = variants.PRACTICAL.surface(table.params("bea", ID)).control_points
        assert np.array_equal(np.array(json.loads(net)), mine)
        assert not np.array_equal(mine, variants.PRACTICAL.surface(None).control_points)
        numbers = ", ".join(f"{x:.10g}" for x in bea)
        assert run(f"answer = ({numbers})\nr = check.own_surface(answer)\nprint(r.passed)").strip() == "True"
        theirs = ", ".join(f"{x:.10g}" for x in ada)
        reply = run(f"answer = ({theirs})\nr = check.own_surface(answer)\nprint(r.passed)\nprint(r)")
        assert reply.startswith("False") and "the variant of bea" in reply
        assert "does not show them" in reply and f"{bea[1]:.4f}" not in reply  # the check keeps her numbers back
        reply = run(f"import numpy as np\nanswer = tuple(np.array([{numbers}]))\nr = check.own_surface(answer)\n"
                    "print(r.status)\nprint(r)")
        assert reply.startswith("error") and "not numbers as written" in reply  # the grader would read code
        shown = run("import os\nos.environ['JUPYTERHUB_USER'] = 'zed'\ns = lab.my_surface()\n"
                    "print(s.variant.status)\nprint(s.variant)\n"
                    "print(bool((s.control_points == lab.surfaces.practical().control_points).all()))")
        assert shown.splitlines() == ["not on roster", shown.splitlines()[1], "True"]
        assert "zed is not on the roster" in shown
    finally:
        kc.stop_channels()
        km.shutdown_kernel(now=True)
    assert variants.resolve(ID).status == "common"  # here, outside any hand-out: the common surface


# -- the grader --------------------------------------------------------------------------------------------------


def test_own_numbers_get_full_marks_and_a_classmates_numbers_none(graded):
    results = graded["results"]
    print("\nstudent | score | own_surface | notes (private notes)")
    for s in ("ada", "bea", "cy", "dan", "eve", "zed"):
        r = results[s]
        print(f"{s} | {r.score:g}/{r.max_score:g} | {own_surface(r)['score']:g} | {r.notes} ({r.private_notes})")
    for s in ("ada", "bea"):  # their own correct solutions
        r = results[s]
        assert (r.score, r.max_score) == (12, 12) and not r.notes and not r.private_notes, r.text()
    for s, owner in (("cy", "ada"), ("dan", "bea")):  # ada's notebook handed in by cy; bea's numbers in dan's
        r = results[s]
        task = own_surface(r)
        assert task["score"] == 0 and r.score == 10 and r.max_score == 12, r.text()
        assert r.private_notes == [(f"own_surface: these numbers answer the variant of another student ({owner}), "
                                    f"not {s}'s own")]
        assert owner not in r.text() and owner not in json.dumps(r.gradescope())  # what the student may see
    assert graded["own"]["ada"][1] != graded["own"]["cy"][1]


def test_the_instructor_sees_whose_numbers_they_are_in_summary_csv(graded):
    rows = {r["student"]: r for r in csv.DictReader(io.StringIO((graded["reports"] / "summary.csv").read_text()))}
    assert "answer the variant of another student (ada)" in rows["cy"]["notes"]
    assert "answer the variant of another student (bea)" in rows["dan"]["notes"]
    assert rows["ada"]["notes"] == "" and rows["ada"]["tasks"] == "visualize_curvature=10/10; own_surface=2/2"
    report = json.loads((graded["reports"] / f"cy__{ID}.json").read_text())
    assert report["private_notes"] and "ada" not in (graded["reports"] / f"cy__{ID}.txt").read_text()
    assert json.loads((graded["reports"] / "run.json").read_text())["variants"] == graded["table"]  # for --resume


def test_code_for_numbers_and_a_student_without_a_variant(graded):
    eve, zed = graded["results"]["eve"], graded["results"]["zed"]
    task = own_surface(eve)
    assert task["score"] == 0 and task["status"] == "error" and eve.score == 10, eve.text()
    assert "not numbers as written" in eve.text() and "runs no code" in eve.text()
    assert own_surface(zed)["score"] == 1 and zed.score == 12, zed.text()  # graded on the common surface …
    assert zed.notes == ["zed is not in the variants table: own_surface is graded on the common surface"]  # … said so


def test_a_per_student_notebook_needs_the_table_and_the_options_go_together(handout, tmp_path, capsys):
    stamped = tmp_path / "bea" / f"{ID}.ipynb"
    stamped.parent.mkdir()
    shutil.copy(handout["out"] / "exercises" / "en" / f"{ID}.ipynb", stamped)
    result = notebook.grade_notebook(stamped)
    assert "per-student hand-out" in result.error and "--variants" in result.error
    assert (result.score, result.max_score) == (0, 12) and handout["table"].id in result.error
    table = str(handout["out"] / variants.TABLE)
    with pytest.raises(SystemExit):
        grade.main([str(stamped), "--variants", table])
    assert "needs --student" in capsys.readouterr().err
    assert grade.main([str(stamped.parent), "--variants", str(tmp_path / "missing.json")]) == 2
    assert "--variants" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        release.main([str(tmp_path / "out"), "--per-student", str(_file(tmp_path / "roster.txt", b"ada\nbea\n"))])
    assert "--per-student and --secret-file go together" in capsys.readouterr().err
