"""Rigid bodies: principal moments, full inertia tensors, solids, composites and meshes.

A body is simulated in its principal axes, where Euler's equations are diagonal, but the
user speaks in the body's own axes (a CAD model's, an assembly's): the core finds the
rotation ``R`` from a tensor's principal axes to the user's (its columns are the principal
axes in user coordinates), and a run turns the start into principal axes once,
``ω_p = Rᵀ ω``, ``q_p = q ⊗ q_R``, and the frames back once at the end, ``ω = R ω_p``,
``q = q_p ⊗ q_R*``, in the core: ``traj.omega`` and ``traj.q`` are the rates and the attitude
of the user's axes. :meth:`Body.to_principal` and :meth:`Body.to_user` make the same change
for other uses.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _core
from ._args import as_array, as_float, check_size
from ._files import ReadError, as_path, open_regular, size_of
from .mass import (
    MeshError,
    apply,
    mesh_moments,
    box_tensor,
    cylinder_tensor,
    ellipsoid_tensor,
    parallel_axis,
    quaternion_of,
    quaternion_product,
)
from .shapes import Shape, box_shape, cylinder_shape, ellipsoid_shape, mesh_shape
from . import wingnut
from .wingnut import hex_nut_mesh, wing_positions

__all__ = ["Body", "InertiaWarning", "MeshError", "as_body", "TENSOR_HINT",
           "SYMMETRY_TOLERANCE", "NEAR_SYMMETRY"]

TENSOR_HINT = ("for one body's 3×3 inertia tensor use `dz.Body.from_tensor(T)`; for several "
               "bodies' principal moments pass a list of Bodies, `[dz.Body(m) for m in "
               "moments]`")
"""What to say to a user whose 3×3 array could be a tensor or three bodies."""


MAX_MESH_BYTES = 1 << 30
"""The largest mesh file :meth:`Body.load` reads (1 GiB, some 20 million triangles in a
binary STL)."""


PAPER_INERTIA = (52.0833, 27.0833, 41.6666)
"""The paper's principal moments (Ix, Iy, Iz), as printed. The box formula gives them with x
and y swapped (erratum 2, see the README); either way z is the intermediate axis."""


SYMMETRY_TOLERANCE: float = _core.SYMMETRY_TOLERANCE
"""Two principal moments within this relative difference (``|Ia − Ib| ≤ 1e-9 · max(Ia, Ib)``)
count as equal: the body is a symmetric top, with no intermediate axis, no flips and an
infinite :func:`~dzhanibekov.flip_period`, decided in the core for every model and method.
Moments from a mesh, a composite or a tensor with products of inertia carry round-off of
1e-16 to 1e-13 (relative), so an axisymmetric part's equal moments come out a few ulps apart;
1e-9 is far above that and far below anything a measurement resolves."""

NEAR_SYMMETRY: float = _core.NEAR_SYMMETRY
"""Moments closer than this (1e-6, relative) but not within :data:`SYMMETRY_TOLERANCE` make a
nearly symmetric top: a Body given by moments, a tensor, a mesh or parts warns
(:class:`InertiaWarning`), since its flips are the slow precession of the transverse rates and
their count depends on digits no measurement fixes. 1e-6 covers, among others, an
axisymmetric part read from a single-precision STL file (coordinates to 6e-8), whose equal
moments may come out that far apart. The solids (:meth:`Body.box`, :meth:`Body.cylinder`, …)
do not warn: their moments follow exactly from the dimensions given."""


class InertiaWarning(UserWarning):
    """Principal moments that no real mass distribution has (the triangle inequality fails),
    or two moments so close (within :data:`NEAR_SYMMETRY`, not :data:`SYMMETRY_TOLERANCE`)
    that the flips depend on digits no measurement fixes."""


class Body:
    """A rigid body given by its principal moments of inertia about body axes x, y, z.

    :attr:`inertia` means the same for every body: the principal moments in the body frame's
    order, each about the principal axis nearest the body's own x, y, z (the columns of
    :attr:`principal_axes`, in that order), so a box's, a mesh's and a tensor's moments read
    as ``(Ix, Iy, Iz)`` of the axes they were given in; :attr:`principal_moments` gives them
    sorted, with their axes :attr:`principal_directions`.

    Two moments equal within :data:`SYMMETRY_TOLERANCE` (1e-9, relative) make a symmetric
    top: no intermediate axis (:attr:`intermediate_axis` is None), no flips, an infinite
    flip period, whether the moments are exactly equal (``Body.cylinder``) or equal to
    round-off (a mesh of a cylinder).

    Other constructors build a body from a full inertia tensor (:meth:`from_tensor`), a solid
    (:meth:`box`, :meth:`cylinder`, :meth:`sphere`, :meth:`ellipsoid`), parts
    (:meth:`compose`), a triangle mesh (:meth:`from_mesh`, :meth:`load`) or the wing nut of
    the paper's Fig. 1 (:meth:`wing_nut`); such bodies also know their mass, centre of mass
    and shape, which the pictures draw.

    Parameters
    ----------
    inertia : array_like, shape (3,)
        ``(Ix, Iy, Iz)``, positive and finite, in any consistent units.

    Raises
    ------
    TypeError
        If `inertia` is not three real numbers.
    ValueError
        If a moment is not positive and finite, or the moments differ by more than 1e150;
        a 3×3 array (a tensor: use :meth:`from_tensor`).

    Warns
    -----
    InertiaWarning
        If one moment exceeds the sum of the other two: every real body has
        ``Ix <= Iy + Iz`` (and likewise for y, z), so such moments describe no body, though
        Euler's equations still run. Also if two moments are within :data:`NEAR_SYMMETRY`
        (1e-6) of each other but not within :data:`SYMMETRY_TOLERANCE`: a nearly symmetric
        top, whose flips depend on digits no measurement fixes (so do :meth:`from_tensor`,
        :meth:`compose`, :meth:`from_mesh` and :meth:`load`; the solids, exact by their
        dimensions, do not).

    Examples
    --------
    >>> Body(inertia=(52.0833, 27.0833, 41.6666)).intermediate_axis
    2
    >>> Body.box(20, 10, 15).inertia[0]  # m (b² + c²) / 12
    27.083333333333332
    >>> Body.cylinder(3, 20).intermediate_axis is None  # a symmetric top
    True
    """

    __slots__ = ("_core", "_axes", "_q_axes", "_mass", "_com", "_shape", "_parts")

    def __init__(self, inertia: Any) -> None:
        if _is_square(inertia):
            raise ValueError(f"`inertia` must be three principal moments, got a 3×3 array; "
                             f"{TENSOR_HINT}")
        ix, iy, iz = as_array("inertia", inertia, "(3,)", last=3, ndim=(1,)).tolist()
        self._fill(_core.RigidBody((ix, iy, iz)))
        _warn_if_unphysical(self._core)

    def _fill(self, core: _core.RigidBody, *, mass: float | None = None,
              com: np.ndarray | None = None, shape: Shape | None = None,
              parts: tuple[Any, ...] = ()) -> None:
        """Fills a Body's slots (the one place that does); the tensor and its principal
        frame are the core's."""
        self._core = core
        axes = None if core.is_principal else np.array(core.principal_axes)
        self._axes = axes
        self._q_axes = None if axes is None else quaternion_of(axes)
        self._mass = mass
        self._com = np.zeros(3) if com is None else com
        self._shape = shape
        self._parts = parts

    # -- construction ------------------------------------------------------------------

    @classmethod
    def box(cls, a: float, b: float, c: float, mass: float = 1.0) -> Body:
        """A solid box with edges `a`, `b`, `c` along x, y, z: ``Ix = m (b² + c²) / 12``, etc.

        Examples
        --------
        >>> Body.box(2, 2, 2, mass=3.0).inertia
        (2.0, 2.0, 2.0)
        """
        edges = [as_float(n, v, positive=True) for n, v in (("a", a), ("b", b), ("c", c))]
        mass = as_float("mass", mass, positive=True)
        body = cls.__new__(cls)
        ea, eb, ec = edges
        body._fill(_core.RigidBody.from_box(ea, eb, ec, mass), mass=mass,
                   shape=box_shape(ea, eb, ec, faces=True))
        return body

    @classmethod
    def cylinder(cls, radius: float, height: float, mass: float = 1.0) -> Body:
        """A solid circular cylinder with its axis along z: ``Iz = m r² / 2``,
        ``Ix = Iy = m (3 r² + h²) / 12`` (Goldstein, *Classical Mechanics*, or any table of
        moments of inertia).

        Examples
        --------
        >>> Body.cylinder(1.0, 2.0, mass=12.0).inertia
        (7.0, 7.0, 6.0)
        """
        r = as_float("radius", radius, positive=True)
        h = as_float("height", height, positive=True)
        m = as_float("mass", mass, positive=True)
        return cls._solid(np.diag(cylinder_tensor(r, h, m)), m, cylinder_shape(r, h),
                          "`radius`, `height` and `mass`")

    @classmethod
    def sphere(cls, radius: float, mass: float = 1.0) -> Body:
        """A solid ball: ``I = 2 m r² / 5`` about every axis.

        Examples
        --------
        >>> Body.sphere(1.0, mass=5.0).inertia
        (2.0, 2.0, 2.0)
        """
        r = as_float("radius", radius, positive=True)
        return cls.ellipsoid(r, r, r, mass)

    @classmethod
    def ellipsoid(cls, a: float, b: float, c: float, mass: float = 1.0) -> Body:
        """A solid ellipsoid with semi-axes `a`, `b`, `c` along x, y, z:
        ``Ix = m (b² + c²) / 5``, etc.

        Examples
        --------
        >>> Body.ellipsoid(1.0, 2.0, 3.0, mass=5.0).inertia
        (13.0, 10.0, 5.0)
        """
        semi = [as_float(n, v, positive=True) for n, v in (("a", a), ("b", b), ("c", c))]
        m = as_float("mass", mass, positive=True)
        sa, sb, sc = semi
        return cls._solid(np.diag(ellipsoid_tensor(sa, sb, sc, m)), m,
                          ellipsoid_shape(sa, sb, sc), "`a`, `b`, `c` and `mass`")

    @classmethod
    def _solid(cls, moments: np.ndarray, mass: float, shape: Shape, names: str) -> Body:
        body = cls.__new__(cls)
        ix, iy, iz = (float(x) for x in moments)
        try:
            core = _core.RigidBody((ix, iy, iz))
        except ValueError as exc:
            raise ValueError(f"{names} give principal moments {(ix, iy, iz)} out of range: "
                             f"{exc}") from None
        body._fill(core, mass=mass, shape=shape)
        return body

    @classmethod
    def from_tensor(cls, tensor: Any, mass: float | None = None) -> Body:
        """A body given by its inertia tensor about its centre of mass, in the user's axes.

        The tensor carries the products of inertia with a minus sign off the diagonal, so
        that the angular momentum is ``L = T ω``::

            T = [[ Ixx, -Ixy, -Ixz],     Ixx = ∫ (y² + z²) dm,  Ixy = ∫ x y dm, …
                 [-Ixy,  Iyy, -Iyz],
                 [-Ixz, -Iyz,  Izz]]

        (some CAD programs print ``Ixy`` itself in that place: negate their products). The
        body's principal moments are the eigenvalues of ``T``, sorted ascending, and its
        principal axes the eigenvectors, the columns of a proper rotation ``R``
        (``T = R diag(I) Rᵀ``, ``det R = +1``). Runs take and return ``omega`` and ``q`` in
        the user's axes (see :mod:`dzhanibekov.body`).

        Parameters
        ----------
        tensor : array_like, shape (3, 3)
            Symmetric (to 1e-10 of its largest entry; the mean of it and its transpose is
            used) and positive definite, at any scale float64 holds. A diagonal tensor's
            moments are taken exactly; with products of inertia the eigensolver finds each
            moment to about ε (2.2e-16) times the largest, so a moment far smaller than the
            largest (a thin rod's, 1e-15 of it) keeps few digits, and one within 4ε of the
            largest is refused as singular to round-off.
        mass : float, optional
            The body's mass, needed only to :meth:`compose` it with others.

        Raises
        ------
        ValueError
            A tensor that is not 3×3, finite, symmetric or positive definite (to round-off).

        Examples
        --------
        >>> body = Body.from_tensor([[2.0, -0.5, 0.0], [-0.5, 2.0, 0.0], [0.0, 0.0, 3.0]])
        >>> [round(i, 12) for i in body.inertia]
        [1.5, 2.5, 3.0]
        >>> round(float(np.linalg.det(body.principal_axes)), 12)
        1.0
        """
        t = as_array("tensor", tensor, "(3, 3)", last=3, ndim=(2,))
        if t.shape != (3, 3):
            raise ValueError(f"`tensor` must have shape (3, 3), got {t.shape}")
        m = None if mass is None else as_float("mass", mass, positive=True)
        return cls._of_tensor(t, m, None, None, (), "tensor")

    @classmethod
    def _of_tensor(cls, tensor: np.ndarray, mass: float | None, com: np.ndarray | None,
                   shape: Shape | None, parts: tuple[Any, ...], name: str) -> Body:
        if not np.isfinite(tensor).all():
            raise ValueError(f"`{name}` is not finite in float64 (its moments, mass × "
                             f"length², exceed {np.finfo(np.float64).max:.3g}); scale it down")
        try:
            core = _core.RigidBody.from_tensor(np.asarray(tensor, dtype=np.float64).tolist())
        except ValueError as exc:
            if name == "tensor":
                raise
            raise type(exc)(f"{name}: {exc}") from None
        body = cls.__new__(cls)
        body._fill(core, mass=mass, com=com, shape=shape, parts=parts)
        _warn_if_unphysical(core)
        return body

    @classmethod
    def _restored(cls, tensor: np.ndarray, mass: float | None, com: np.ndarray,
                  shape: Shape | None = None) -> Body:
        """A body as a file keeps it: its tensor, mass, centre of mass and the outline the
        pictures draw (not a composite's parts)."""
        with warnings.catch_warnings():  # warned about when it was made
            warnings.simplefilter("ignore", InertiaWarning)
            body = cls._of_tensor(np.asarray(tensor, dtype=np.float64), mass,
                                  np.asarray(com, dtype=np.float64), shape, (), "body_tensor")
        return body

    @classmethod
    def compose(cls, parts: Sequence[Any]) -> Body:
        """A body assembled from parts: ``[(part, position, q), ...]``.

        Each `part` is a :class:`Body` with a mass, placed with its centre of mass at
        `position` and turned by the unit quaternion `q` (scalar first; may be left out, for
        no turn) in the assembly's axes. The mass is the sum; the tensor, about the composite
        centre of mass (:attr:`center_of_mass`, in the assembly's coordinates), is the sum
        of each part's tensor turned into the assembly's axes, ``M(q) T Mᵀ(q)``, plus its
        parallel-axis term ``m (|d|² 𝟙 − d dᵀ)`` for its offset ``d`` from that centre
        (Huygens–Steiner). The parts' shapes are kept for drawing.

        Raises
        ------
        ValueError
            No parts, a part without a mass (build it with one), or a bad position or
            quaternion (naming the part).

        Examples
        --------
        >>> two = Body.compose([(Body.box(1, 1, 1), (-1, 0, 0), (1, 0, 0, 0)),
        ...                     (Body.box(1, 1, 1), (1, 0, 0))])
        >>> two.mass, two.inertia[0]
        (2.0, 0.3333333333333333)
        """
        if isinstance(parts, (str, bytes)) or not isinstance(parts, Sequence) or not parts:
            raise ValueError("`parts` must be a non-empty list of (part, position, q) tuples")
        masses, positions, tensors, shapes = [], [], [], []
        for k, item in enumerate(parts):
            if isinstance(item, Body) or not isinstance(item, (tuple, list)) \
                    or len(item) not in (2, 3):
                raise ValueError(f"`parts[{k}]` must be (part, position) or "
                                 f"(part, position, q), got {item!r}")
            part, position = item[0], item[1]
            q = item[2] if len(item) == 3 else (1.0, 0.0, 0.0, 0.0)
            if not isinstance(part, Body):
                raise TypeError(f"`parts[{k}]`'s part must be a Body, got "
                                f"{type(part).__name__}")
            if part.mass is None:
                raise ValueError(f"`parts[{k}]` has no mass; build it with one (Body.box, "
                                 "cylinder, sphere, ellipsoid, from_mesh or "
                                 "from_tensor(..., mass=m))")
            p = as_array(f"parts[{k}] position", position, "(3,)", last=3, ndim=(1,))
            qa = as_array(f"parts[{k}] q", q, "(4,)", last=4, ndim=(1,))
            biggest = float(np.abs(qa).max())
            if not biggest > 0:
                raise ValueError(f"`parts[{k}] q` must be a non-zero quaternion")
            qa = qa / biggest  # then its norm neither underflows (1e-300) nor overflows
            turn = rotation_matrix(qa / float(np.linalg.norm(qa)))
            masses.append(part.mass)
            positions.append(p)
            tensors.append(turn @ part.tensor @ turn.T)
            shapes.append(part.shape.placed(turn, p) if part.shape is not None else None)
        mass = float(sum(masses))
        com = np.sum([m * p for m, p in zip(masses, positions)], axis=0) / mass
        tensor = sum(parallel_axis(t, m, p - com)
                     for t, m, p in zip(tensors, masses, positions))
        drawn = [s.placed(np.eye(3), -com) for s in shapes if s is not None]
        shape = Shape.union(drawn) if drawn else None
        kept = tuple((part[0], tuple(positions[k]), part[2] if len(part) == 3 else
                      (1.0, 0.0, 0.0, 0.0)) for k, part in enumerate(parts))
        return cls._of_tensor(np.asarray(tensor), mass, np.asarray(com), shape, kept,
                              "the composite's tensor")

    @classmethod
    def from_mesh(cls, vertices: Any, faces: Any, mass: float | None = None,
                  density: float | None = None) -> Body:
        """A uniform solid bounded by a closed triangle mesh.

        Volume, centre of mass and the tensor follow from the divergence theorem, as a sum
        over the faces of signed tetrahedra, exact for polyhedra (Mirtich 1996; Eberly,
        *Polyhedral Mass Properties*; see :mod:`dzhanibekov.mass`).

        A mesh of several closed parts is the sum of the parts: they must not overlap (the
        overlap would count twice). Parts whose surfaces cross, or one inside another, are
        refused; parts that touch, a cavity (a part wound inward inside another) and an
        island in a cavity are kept (see :func:`dzhanibekov.mass.check_parts_apart` for what
        the check sees). Coordinates of any size float64 holds are taken (the integrals are
        scaled to unit size); the moments, mass × size², must be representable.

        Parameters
        ----------
        vertices : array_like, shape (V, 3)
        faces : array_like of int, shape (F, 3)
            Triangles, counter-clockwise seen from outside; every edge shared by exactly two
            faces that run it in opposite directions.
        mass, density : float, optional
            One or neither (then ``density = 1``); the mass is ``density × volume``.

        Raises
        ------
        MeshError
            (a ValueError) An open, non-manifold, inconsistently oriented or inward-wound
            mesh, one without volume, or one of overlapping parts.
        ValueError
            A mass (``density`` × volume) or moments beyond float64, naming the limit.

        Examples
        --------
        >>> v = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
        >>> f = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
        >>> round(Body.from_mesh(v, f).mass, 12)  # a unit corner tetrahedron, volume 1/6
        0.166666666667
        """
        v = as_array("vertices", vertices, "(V, 3)", last=3, ndim=(2,))
        try:
            f = np.asarray(faces)
        except Exception as exc:  # ragged lists and the like
            raise TypeError(f"`faces` must be an integer array of shape (F, 3): {exc}") from None
        if f.dtype.kind not in "iu" or f.ndim != 2 or f.shape[1] != 3:
            raise TypeError(f"`faces` must be integers of shape (F, 3), got {f.dtype} "
                            f"{f.shape}")
        f = f.astype(np.int64)
        if mass is not None and density is not None:
            raise ValueError("give `mass` or `density`, not both")
        m = None if mass is None else as_float("mass", mass, positive=True)
        rho = 1.0 if density is None else as_float("density", density, positive=True)
        volume, centroid, gyration = mesh_moments(v, f)
        if m is None:
            m = rho * volume
            if not 0 < m < np.inf:
                raise ValueError(
                    f"the mesh's mass, `density` × its volume = {rho:.3g} × {volume:.3g}, is "
                    f"{'beyond' if m else 'below'} what float64 holds (up to "
                    f"{np.finfo(np.float64).max:.3g}); give `mass` instead, or scale the "
                    "mesh")
        with np.errstate(over="ignore", under="ignore"):
            tensor = gyration * m
        info = np.finfo(np.float64)
        if not np.isfinite(tensor).all() or not (np.diag(tensor) >= info.tiny).all():
            big = not np.isfinite(tensor).all()
            raise ValueError(
                f"the mesh's moments of inertia, its mass ({m:.3g}, from `mass` or "
                f"`density`) × its size² ({float(np.abs(gyration).max()):.3g}), "
                + (f"exceed float64's {info.max:.3g}; give a smaller" if big else
                   f"fall below float64's {info.tiny:.3g}; give a larger")
                + " `mass` or `density`, or scale the mesh")
        shape = mesh_shape(v - centroid, f)
        return cls._of_tensor(tensor, m, centroid, shape, (), "the mesh's tensor")

    @classmethod
    def load(cls, path: str | os.PathLike[str], mass: float | None = None,
             density: float | None = None) -> Body:
        """A uniform solid from a mesh file (STL, OBJ, PLY, … anything trimesh reads), as
        :meth:`from_mesh`. Needs the optional ``mesh`` extra: ``pip install "dzhanibekov[mesh]"``.

        The file must be a regular file (a FIFO or a device is refused at once) of at most
        :data:`MAX_MESH_BYTES`.

        Raises
        ------
        ImportError
            trimesh is not installed.
        MeshError
            (a ValueError) The file is missing, not a regular file, too large, cannot be read
            as one triangle mesh (whatever trimesh raised, named; a format that needs a
            module trimesh lacks names that module), or the mesh is not closed (see
            :meth:`from_mesh`).
        """
        try:
            import trimesh  # type: ignore[import-untyped, import-not-found, unused-ignore]
        except ImportError:
            raise ImportError("`Body.load` reads mesh files with trimesh, an optional "
                              "dependency: pip install \"dzhanibekov[mesh]\" (or pip "
                              "install trimesh)") from None
        p = as_path(path)
        what = "a mesh file (STL, OBJ, PLY, … that trimesh reads)"
        try:
            with open_regular(p, what) as f:
                size = size_of(f)
        except ReadError as exc:
            raise MeshError(f"`path` {str(p)!r} cannot be read as a mesh ({exc.why})") \
                from None
        if size > MAX_MESH_BYTES:
            raise MeshError(f"`path` {str(p)!r} holds {size} bytes, more than the "
                            f"{MAX_MESH_BYTES} (MAX_MESH_BYTES) Body.load reads")
        check_size(4 * size, f"reading the mesh {p}", "simplify the mesh")
        try:
            mesh: Any = trimesh.load(os.fspath(p), force="mesh", process=True)
            vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
        except (MemoryError, KeyboardInterrupt):
            raise
        except ModuleNotFoundError as exc:
            raise MeshError(f"`path` {str(p)!r} cannot be read as a mesh: reading "
                            f"{p.suffix or 'this'} files needs the module {exc.name!r}, "
                            "which is not installed") from None
        except Exception as exc:  # trimesh raises all kinds (IndexError, KeyError, …)
            raise MeshError(f"`path` {str(p)!r} cannot be read as a mesh "
                            f"({type(exc).__name__}: {str(exc)[:200]})") from None
        try:
            return cls.from_mesh(vertices, faces, mass=mass, density=density)
        except MeshError as exc:
            raise MeshError(f"`path` {str(p)!r} is no closed mesh: {exc}") from None

    @classmethod
    def wing_nut(cls) -> Body:
        """The wing nut of the paper's Fig. 1 (the one V. Dzhanibekov saw flip in 1985): a
        steel hex nut with two wings, in millimetres and grams.

        Proportions (roughly an M8 nut): hexagon 13 mm across flats (flats facing ±x),
        8 mm high (z from −4 to 4), an 8 mm bore (a 12-gon); two wings, plates 12 mm long
        (x), 2.5 mm thick (y) and 14 mm high (z from −4 to 10), set against the flats at
        ±x; density 7.85e-3 g/mm³ (steel). The bolt axis z is the intermediate axis: spun
        about it, the nut flips.

        Examples
        --------
        >>> nut = Body.wing_nut()
        >>> round(nut.mass, 2), [round(i) for i in nut.inertia]  # g and g·mm², about x, y, z
        (12.77, [269, 1375, 1306])
        >>> nut.principal_axes[:, nut.intermediate_axis]  # the bolt axis z
        array([0., 0., 1.])
        """
        vertices, faces = hex_nut_mesh()
        nut = cls.from_mesh(vertices, faces, density=wingnut.DENSITY)
        a, b, c = wingnut.WING
        wing = cls.box(a, b, c, mass=wingnut.DENSITY * a * b * c)
        left, right = wing_positions()
        return cls.compose([(nut, nut.center_of_mass), (wing, left), (wing, right)])

    # -- properties ----------------------------------------------------------------------

    @property
    def inertia(self) -> tuple[float, float, float]:
        """The principal moments ``(Ix, Iy, Iz)`` in the body frame's order, for every kind
        of body: each about the principal axis nearest the body's own x, y, z (the columns of
        :attr:`principal_axes`). For a body given in principal axes (a box, a cylinder, a
        mesh aligned with its axes, to round-off) it is the tensor's diagonal, in the order
        of x, y, z; ascending only where an axis lies midway between two of the body's
        (a tensor turned 45°). Runs, files, scenes and figures read this order; sorted
        moments are :attr:`principal_moments`.

        Examples
        --------
        >>> Body.box(20, 10, 15).inertia  # along x, y, z, not sorted
        (27.083333333333332, 52.08333333333333, 41.666666666666664)
        """
        return self._core.inertia

    @property
    def principal_moments(self) -> tuple[float, float, float]:
        """The principal moments sorted ascending, ``I1 <= I2 <= I3`` (minor, intermediate,
        major), whatever the body's axes; their axes are :attr:`principal_directions`.

        Examples
        --------
        >>> Body.box(20, 10, 15).principal_moments
        (27.083333333333332, 41.666666666666664, 52.08333333333333)
        """
        a, b, c = sorted(self._core.inertia)
        return (a, b, c)

    @property
    def principal_directions(self) -> np.ndarray:
        """The axes of :attr:`principal_moments` (ascending) as the columns of a proper
        rotation (user axes from sorted principal axes, ``det = +1``: the last column's sign
        is turned where the sorting alone would mirror the frame), shape (3, 3).

        Examples
        --------
        >>> Body.box(20, 10, 15).principal_directions  # x, z, y; the last turned: det +1
        array([[ 1.,  0.,  0.],
               [ 0.,  0., -1.],
               [ 0.,  1.,  0.]])
        """
        order = np.argsort(np.array(self._core.inertia), kind="stable")
        axes = self.principal_axes[:, order]
        if np.linalg.det(axes) < 0:
            axes[:, 2] = -axes[:, 2]
        return axes + 0.0  # no negative zeros

    @property
    def tensor(self) -> np.ndarray:
        """The inertia tensor about the centre of mass, in the user's axes (products of
        inertia negated off the diagonal, ``L = T ω``), shape (3, 3)."""
        return np.array(self._core.tensor)

    @property
    def principal_axes(self) -> np.ndarray:
        """The principal axes as the columns of a proper rotation ``R`` (user axes from
        principal axes: ``T = R diag(inertia) Rᵀ``); the identity for a body given by its
        principal moments."""
        return np.eye(3) if self._axes is None else self._axes.copy()

    @property
    def mass(self) -> float | None:
        """The mass, or None for a body given only by its moments."""
        return self._mass

    @property
    def center_of_mass(self) -> np.ndarray:
        """Where the centre of mass is in the coordinates the body was built in (an
        assembly's, a mesh's); the origin for the solids. Shape (3,)."""
        return self._com.copy()

    @property
    def shape(self) -> Shape | None:
        """What the pictures draw, in the user's axes about the centre of mass; None for a
        body given only by its moments or tensor (drawn as the paper's box)."""
        return self._shape

    @property
    def parts(self) -> tuple[tuple[Body, tuple[float, ...], Any], ...]:
        """A composite's parts as given to :meth:`compose`; empty for other bodies."""
        return self._parts

    @property
    def intermediate_axis(self) -> int | None:
        """The axis (0, 1, 2: the entry of `inertia`, the column of `principal_axes`) of the
        intermediate moment, about which spin is unstable; None for a symmetric top (two
        moments equal within :data:`SYMMETRY_TOLERANCE`, 1e-9 relative)."""
        return self._core.intermediate_axis

    @property
    def asymmetry(self) -> float:
        """The smallest relative difference of two principal moments,
        ``min |Ia − Ib| / max(Ia, Ib)``: at most :data:`SYMMETRY_TOLERANCE` for a symmetric
        top.

        Examples
        --------
        >>> Body((2.0, 3.0, 4.0)).asymmetry  # 3 and 4: 1/4
        0.25
        """
        return self._core.asymmetry

    # -- the change of axes at the edge of a run -------------------------------------------

    @property
    def is_principal(self) -> bool:
        """Whether the user's axes are the principal axes (no change of axes in a run)."""
        return self._axes is None

    def to_principal(self, omega: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rates (..., 3) and attitudes (..., 4) of the user's axes turned into those of the
        principal axes: ``ω_p = Rᵀ ω``, ``q_p = q ⊗ q_R``; the inputs themselves for a body
        in principal axes."""
        if self._axes is None:
            return omega, q
        return apply(self._axes.T, omega), quaternion_product(q, self._q_axes)

    def to_user(self, omega: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The inverse of :meth:`to_principal`: ``ω = R ω_p``, ``q = q_p ⊗ q_R*``."""
        if self._axes is None:
            return omega, q
        conj = self._q_axes * np.array([1.0, -1.0, -1.0, -1.0])
        return apply(self._axes, omega), quaternion_product(q, conj)

    # -- the rest --------------------------------------------------------------------------

    def __repr__(self) -> str:
        """What the body is: its moments or tensor, with its mass and, if not at the
        origin, its centre of mass (what :func:`dzhanibekov.save` keeps of it).

        Examples
        --------
        >>> Body((1.0, 2.0, 3.0))
        Body(inertia=(1.0, 2.0, 3.0))
        >>> Body.box(1, 2, 3, mass=2.0)
        Body(inertia=(2.1666666666666665, 1.6666666666666665, 0.8333333333333333), mass=2.0)
        """
        extra = "" if self._mass is None else f", mass={self._mass!r}"
        if self._com.any():
            extra += f", center_of_mass={self._com.tolist()!r}"
        if self._axes is None:
            return f"Body(inertia={self.inertia!r}{extra})"
        return f"Body.from_tensor({self.tensor.tolist()!r}{extra})"

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Body):
            return NotImplemented  # a System without parts compares with its body
        return (self.inertia == other.inertia
                and np.array_equal(self.tensor, other.tensor)
                and np.array_equal(self.principal_axes, other.principal_axes))

    def __hash__(self) -> int:
        return hash(self.inertia)


def principal_body(inertia: Any) -> Body:
    """A Body of moments the core has already accepted (no second warning)."""
    body = Body.__new__(Body)
    ix, iy, iz = (float(i) for i in inertia)
    body._fill(_core.RigidBody((ix, iy, iz)))
    return body


def tensor_moments(tensor: Any) -> tuple[float, float, float]:
    """The principal moments of a tensor the core has accepted, in the body frame's order (as
    :attr:`Body.inertia` gives them): what a deployment's run reports for its tensor at
    ``t = 0``."""
    rows = np.asarray(tensor, dtype=np.float64).tolist()
    return _core.RigidBody.from_tensor(rows).inertia


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """The paper's trig-free matrix ``M(q)`` of a unit quaternion (scalar first)."""
    w, x, y, z = (float(c) for c in q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def as_body(value: Any, name: str = "body") -> Body:
    """`value` if a Body, else the Body of the principal moments it holds; a failure names
    `name` as well as the moments."""
    if isinstance(value, Body):
        return value
    if _is_square(value):
        raise ValueError(f"`{name}` must be a Body or its principal moments (Ix, Iy, Iz), "
                         f"got a 3×3 array; {TENSOR_HINT}")
    try:
        return Body(value)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"`{name}` must be a Body or its principal moments (Ix, Iy, Iz): "
                        f"{exc}") from None


def _is_square(value: Any) -> bool:
    """Whether `value` is a 3×3 array (a tensor where moments were expected)."""
    try:
        return bool(np.shape(value) == (3, 3))
    except Exception:  # ragged lists and the like: the checks will say so
        return False


def _warn_if_unphysical(core: _core.RigidBody) -> None:
    if SYMMETRY_TOLERANCE < core.asymmetry <= NEAR_SYMMETRY:
        warnings.warn(
            f"principal moments {core.inertia} have two within {core.asymmetry:.2g} of each "
            f"other (relative): a nearly symmetric top, not one (moments within "
            f"{SYMMETRY_TOLERANCE:g} count as equal, dz.SYMMETRY_TOLERANCE); its flips are "
            "the slow precession of its transverse rates and depend on digits no measurement "
            "fixes; make the moments equal for a symmetric top",
            InertiaWarning,
            stacklevel=3,
        )
    if not core.satisfies_triangle_inequality:
        warnings.warn(
            f"principal moments {core.inertia} break the triangle inequality "
            "(each moment of a real body is at most the sum of the other two); "
            "no mass distribution has them",
            InertiaWarning,
            stacklevel=3,
        )
