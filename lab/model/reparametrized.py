"""A surface in a CAD file's own parameters: a NURBS evaluated at mapped parameters (``lab.ReparametrizedSurface``)."""

import numpy as np

from ..geometry import tensor as _tensor
from ..geometry import validation as _v
from ..geometry.derivatives import Derivatives
from .checks import map_values
from .surface import Surface, _check_domain

__all__ = ["ReparametrizedSurface"]


class ReparametrizedSurface(Surface):
    r"""A surface in new parameters: :math:`\mathbf x(u, v) = \mathbf b(s(u), t(v))`, one increasing map per direction.

    A CAD face keeps the parameters of its file (a cylinder's angle) while its exact NURBS form runs in
    others (:mod:`lab.geometry.parameter_maps`); this class evaluates the NURBS at the mapped parameters
    and applies the chain rule, so curvature, geodesics, meshes and trims work in the file's parameters:

    .. math::

        \mathbf x_u = \mathbf b_s s', \quad \mathbf x_v = \mathbf b_t t', \quad
        \mathbf x_{uu} = \mathbf b_{ss} s'^2 + \mathbf b_s s'', \quad
        \mathbf x_{uv} = \mathbf b_{st} s' t', \quad
        \mathbf x_{vv} = \mathbf b_{tt} t'^2 + \mathbf b_t t''.

    The maps increase (:math:`s', t' > 0`), so the normal :math:`\mathbf x_u \times \mathbf x_v` points
    the same way as :math:`\mathbf b_s \times \mathbf b_t` and K, H, k1, k2 are the base surface's.

    Parameters
    ----------
    base : Surface
        The surface in its own parameters (usually a :class:`BSplineSurface`).
    map_u, map_v : callable
        ``map(u)`` returns ``(s, ds/du, d2s/du2)``, arrays of ``u``'s shape
        (e.g. :class:`lab.geometry.parameter_maps.ParameterMap`).
    domain : ((float, float), (float, float))
        The domain in the new parameters; its image lies in the base's domain.
    """

    def __init__(self, base, map_u, map_v, domain, name="reparametrized surface"):
        if not isinstance(base, Surface):
            raise TypeError(f"base must be a lab.Surface; got {type(base).__name__}")
        if not (callable(map_u) and callable(map_v)):
            raise TypeError("map_u and map_v must be callables returning (s, ds, d2s)")
        self.base = base
        self.maps = [map_u, map_v]  # a list: cached results key on its identity (the maps may hold arrays)
        self.domain = _check_domain(domain)
        self.name = name

    def _chain(self, D, su, sv):
        """The derivatives in the new parameters from the base's ``D`` and the maps' values (broadcastable)."""
        (_, du, ddu), (_, dv, ddv) = su, sv
        du, ddu, dv, ddv = (x[..., None] for x in (du, ddu, dv, ddv))
        return Derivatives(D.b, D.bu * du, D.bv * dv, D.buu * du * du + D.bu * ddu, D.buv * du * dv,
                           D.bvv * dv * dv + D.bv * ddv)

    def _point_derivatives(self, u, v, work=None):
        su, sv = map_values(self.maps[0], u, "map_u"), map_values(self.maps[1], v, "map_v")
        return self._chain(self.base._point_derivatives(su[0], sv[0], work), su, sv)

    def _grid_blocks(self, u, v):
        su, sv = map_values(self.maps[0], u, "map_u"), map_values(self.maps[1], v, "map_v")
        for rows, cols, D in self.base._grid_blocks(su[0], sv[0]):
            yield rows, cols, self._chain(D, tuple(x[rows][:, None] for x in su), tuple(x[cols][None, :] for x in sv))

    def _map_points(self, func, u, v):
        return _tensor.map_points(self._point_derivatives, func, u, v)

    def _derivatives(self, u, v):
        u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
        shape = u.shape
        D = self._point_derivatives(u.reshape(-1), v.reshape(-1))
        return D.map(lambda x: x.reshape(shape + x.shape[1:]))

    def third_derivatives(self, u, v):
        r"""As :meth:`Surface.third_derivatives`, by the chain rule from the base's (maps with a method ``third``
        giving :math:`s^{(3)}`, as :class:`lab.geometry.parameter_maps.ParameterMap` has):

        .. math::

            \mathbf x_{uuu} = \mathbf b_{sss} s'^3 + 3\mathbf b_{ss} s' s'' + \mathbf b_s s^{(3)}, \quad
            \mathbf x_{uuv} = (\mathbf b_{sst} s'^2 + \mathbf b_{st} s'')\,t', \quad
            \mathbf x_{uvv} = (\mathbf b_{stt} t'^2 + \mathbf b_{st} t'')\,s', \quad
            \mathbf x_{vvv} = \mathbf b_{ttt} t'^3 + 3\mathbf b_{tt} t' t'' + \mathbf b_t t^{(3)}.
        """
        if not all(callable(getattr(m, "third", None)) for m in self.maps):
            raise NotImplementedError("a reparametrized surface has third derivatives only with maps that have a "
                                      "method third(t)")
        u, v = _v.as_parameters(u, v, self.domain)
        su, sv = map_values(self.maps[0], u, "map_u"), map_values(self.maps[1], v, "map_v")
        D = self.base.derivatives(su[0], sv[0])
        buuu, buuv, buvv, bvvv = self.base.third_derivatives(su[0], sv[0])
        (_, s1, s2), (_, t1, t2) = ((x[..., None] for x in m) for m in (su, sv))
        s3, t3 = (np.asarray(m.third(x), dtype=float)[..., None] for m, x in zip(self.maps, (u, v)))
        return (buuu * s1 ** 3 + 3 * D.buu * s1 * s2 + D.bu * s3, (buuv * s1 * s1 + D.buv * s2) * t1,
                (buvv * t1 * t1 + D.buv * t2) * s1, bvvv * t1 ** 3 + 3 * D.bvv * t1 * t2 + D.bv * t3)

    def _defining(self):
        return (self.base, self.maps, self.domain, self.periodic)

    def __repr__(self):
        return f"ReparametrizedSurface({self.name}, domain={self.domain}, base={self.base!r})"
