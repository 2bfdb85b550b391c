"""Written answers (``lab.teaching.course.written``): the marking CSV an instructor fills in, read back with decimal
commas, semicolons and a byte order mark, a row with more cells than the header refused."""

import re

import pytest

from lab.teaching.course import written
from tests.report_support import text_file


def test_written_points_with_a_decimal_comma(tmp_path):
    head = "student,assignment,question,title,max_points,points,comment,answer\n"
    assert written.read_written(text_file(tmp_path / "a.csv", head + 'ada,04,bfbc93a2,Question,3,"2,5",,text\n'
                                       'ada,04,cafe0001,Other,3,0.5,,"a, b"\n')) == {("ada", "04"): (3.0, 6.0)}
    # a German spreadsheet saves with semicolons (and a byte order mark)
    semi = text_file(tmp_path / "b.csv", "\ufeff" + head.replace(",", ";") + "ada;04;bfbc93a2;Frage;3;2,5;;Text\n")
    assert written.read_written(semi) == {("ada", "04"): (2.5, 3.0)}
    bad = text_file(tmp_path / "c.csv", head + "ada,04,bfbc93a2,Question,3,zwei,,text\n")
    with pytest.raises(ValueError, match="^" + re.escape(f"{bad}, line 2: points and max_points must be numbers; "
                                                         "got 'zwei', '3'") + "$"):
        written.read_written(bad)
    unquoted = text_file(tmp_path / "d.csv", head + "ada,04,bfbc93a2,Question,3,2,5,,text\n")  # would read 2 points
    with pytest.raises(ValueError, match="^" + re.escape(f"{unquoted}, line 2: more cells than the header has "
                                                         'columns; write 2.5, or "2,5" in quotes, in a '
                                                         "comma-separated file") + "$"):
        written.read_written(unquoted)
