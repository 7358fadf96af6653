"""Mechanism: the one contract of every parallel manipulator of imagespace.

The planar image space is the subspace ``(p0, 0, 0, p1, 0, p3, -p2, 0)`` of Study's quadric, so
planar and spatial designs are one kind of object. A :class:`Mechanism` (a
:class:`~imagespace.PlanarParallel`, a :class:`~imagespace.spatial.GoughStewart`, a
:class:`~imagespace.spatial.ThreeRPS`) says how many actuated joints it has, checks a joint vector
(:meth:`Mechanism.check_q`) and a batch of them (:meth:`Mechanism.joint_rows`), solves its inverse
kinematics, keeps its derived and compiled artefacts behind :meth:`Mechanism.cached`, and offers
its direct-kinematics *back ends* (:class:`Backends`: float, proof, exact, counts), plain functions
of ``(mechanism, rows)``. The one front end, :mod:`imagespace.solve.front`, validates, batches,
guards memory and runs the ladder float -> proof -> exact for every mechanism alike; engines
(singular, paths, design, atlas) call the front end with a mechanism, never a facade method.

Imports nothing above :mod:`imagespace.core`.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass, fields
from typing import Any, Callable, Hashable, Optional

import numpy as np
import numpy.typing as npt
from ..exceptions import InputTypeError, RowIndexError

__all__ = ["Mechanism", "Backends", "check_mechanism", "index_rows", "BACKEND_STAGES"]

#: The stages every mechanism's :class:`Backends` must provide (the others are optional).
BACKEND_STAGES = ("solve", "prove", "exact", "counts", "empty", "store", "peak_bytes", "doubt")


@dataclass(frozen=True)
class Backends:
    """The direct-kinematics back ends a mechanism offers, each a plain function.

    The front end (:mod:`imagespace.solve.front`) calls them; they never call the front end or a
    facade method back, and they do not validate user input (the front end has).

    Attributes
    ----------
    methods : tuple of str
        The ``method=`` names the mechanism accepts, the default first.
    solve : callable
        ``solve(m, Q, rows, method, per_call) -> batch``: the floating-point (or compiled)
        stage on the rows ``rows`` (bool mask) of ``Q`` (n, k); other rows come back empty with
        ``row_ok`` False. ``batch.near_singular`` flags every row whose count is not proven.
        ``per_call`` asks it to raise on a continuum instead of masking the row.
    prove : callable
        ``prove(m, Q, batch, rows, method) -> batch``: certify the rows (``certify=True``),
        filling ``certified_roots``, ``certificate_path`` and re-solving rows per row where needed.
    exact : callable
        ``exact(m, q, qf, method, certify) -> result``: one joint vector on the certified (or
        exact) path; ``q`` as given (exact entries kept), ``qf`` its checked floats.
    counts : callable
        ``counts(m, Q, rows) -> (counts, path)``: proven numbers of real modes without the modes.
    empty : callable
        ``empty(m, obstruction, certify) -> result``: the per-call answer "no real mode" that a
        reach bound proved.
    store : callable
        ``store(batch, rows, results, certify)``: write per-row results (from ``exact`` or
        ``empty``; an exception instance masks the row with its message) into a batch.
    peak_bytes : callable
        ``peak_bytes(m, method, certify, n) -> int``: peak memory per row of an ``n``-row batch
        (the memory guard).
    doubt : callable
        ``doubt(m, qf, result) -> str``: the warning text of a per-call answer not proven.
    reach : callable, optional
        ``reach(m, q) -> obstruction or None``: an exact proof that ``q`` has no real mode.
    far : callable, optional
        ``far(m, Q) -> (n,) bool``: rows the float stage does not resolve (sent to ``exact``).
    complex_modes : callable, optional
        ``complex_modes(m, qf, result) -> result``: the per-call result with the non-real
        solutions of one joint vector added.
    exact_methods : tuple of str
        The ``method=`` names that go straight to the exact stage (a spatial ``"exact"``).
    """

    methods: tuple
    solve: Callable
    prove: Callable
    exact: Callable
    counts: Callable
    empty: Callable
    store: Callable
    peak_bytes: Callable
    doubt: Callable
    reach: Optional[Callable] = None
    far: Optional[Callable] = None
    complex_modes: Optional[Callable] = None
    exact_methods: tuple = ()

    def missing(self):
        """The required stages that are not callables (empty for a complete set).

        Examples
        --------
        >>> from imagespace.core.mechanism import Backends
        >>> Backends(("auto",), *([None] * 8)).missing()[:2]
        ['solve', 'prove']
        """
        return [f.name for f in fields(self) if f.name in BACKEND_STAGES and not callable(getattr(self, f.name))]


class Mechanism(abc.ABC):
    """The contract every mechanism implements (planar and spatial alike).

    Subclasses define :attr:`joint_count`, :meth:`check_q`, :meth:`joint_rows`,
    :meth:`inverse_kinematics` and :attr:`backends`, set ``name`` and ``tolerances``, and call
    :meth:`_init_cache` in their constructor. The direct kinematics itself is not a method to
    implement: the subclass binds the front end's functions (``direct_kinematics = front.
    direct_kinematics`` ...), which read :attr:`backends`.

    Examples
    --------
    >>> import imagespace as isp
    >>> m = isp.examples.general_3rpr()
    >>> isinstance(m, isp.Mechanism), m.joint_count
    (True, 3)
    >>> gs, L = isp.examples.dietmaier_1998()
    >>> isinstance(gs, isp.Mechanism), gs.joint_count
    (True, 6)
    """

    name: str
    tolerances: Any
    #: ``"planar"`` (the image space of planar displacements) or ``"study"`` (Study's quadric)
    image_space: str = ""

    @property
    @abc.abstractmethod
    def joint_count(self) -> int:
        """Number of actuated joints (the length of a joint vector)."""

    @abc.abstractmethod
    def check_q(self, q: Any, name: str = "q") -> npt.NDArray[np.float64]:
        """One joint vector ``(k,)`` (or rows ``(n, k)``) as checked floats; raises by name."""

    @abc.abstractmethod
    def joint_rows(self, Q: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.bool_], dict]:
        """Rows of a float array ``(n, k)`` inside the joints' domains: ``(ok, errors)``."""

    @abc.abstractmethod
    def inverse_kinematics(self, pose: Any, *args: Any, **kwargs: Any) -> Any:
        """Joint values at a pose."""

    @property
    @abc.abstractmethod
    def backends(self) -> Optional[Backends]:
        """The direct-kinematics back ends (:class:`Backends`), or None where none is bound."""

    # -- the named cache of derived and compiled artefacts ------------------------------------

    def _init_cache(self) -> None:
        self._symbolic_cache: dict[Hashable, Any] = {}

    @property
    def _artefacts(self) -> dict:
        """The cache dictionary (created on first use by subclasses that do not call
        :meth:`_init_cache`)."""
        cache = self.__dict__.get("_symbolic_cache")
        if cache is None:
            cache = self.__dict__["_symbolic_cache"] = {}
        return cache

    def cached(self, key: Hashable, factory: Callable[[], Any]) -> Any:
        """The artefact stored under ``key``, built by ``factory()`` on first use.

        Every derived or compiled artefact of the design lives here (symbolic polynomials,
        lambdified functions, the compiled kernel, the start system ...), so :meth:`clear_cache`
        frees them all.

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> m.cached("answer", lambda: 42), m.cached("answer", lambda: 0)
        (42, 42)
        """
        cache = self._artefacts
        if key not in cache:
            cache[key] = factory()
        return cache[key]

    def clear_cache(self) -> None:
        """Forget every derived and compiled artefact (they are rebuilt on demand).

        Examples
        --------
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> _ = m.kinematic_polynomial(); m.clear_cache(); len(m.cache_keys())
        0
        """
        self._artefacts.clear()

    def cache_keys(self) -> list[Hashable]:
        """The keys of the artefacts built so far (for inspection).

        Examples
        --------
        >>> import imagespace as isp
        >>> isp.examples.general_3rpr().cache_keys()
        []
        """
        return list(self._artefacts)

    def __getstate__(self) -> dict[str, Any]:
        """The pickled state: the design without the cache.

        A pickled mechanism (sent to a ``dask.distributed`` worker or a process pool) rebuilds
        its derived and compiled artefacts on first use on the other side. Pickled with its cache
        it would carry the compiled kernel's numba dispatcher by value, which the receiver
        compiles again from scratch (measured 22 s for seed 002, against 2.5 s to derive the
        kernel anew and load it from the on-disk numba cache).

        Examples
        --------
        >>> import pickle
        >>> import imagespace as isp
        >>> m = isp.examples.general_3rpr()
        >>> _ = m.kinematic_polynomial()
        >>> copy = pickle.loads(pickle.dumps(m))
        >>> copy.cache_keys(), copy.kinematic_polynomial() == m.kinematic_polynomial()
        ([], True)
        """
        state = self.__dict__.copy()
        state["_symbolic_cache"] = {}
        return state


def check_mechanism(value: Any, name: str = "manipulator", image_space: Optional[str] = "planar") -> Mechanism:
    """Refuse anything but a mechanism that honours the contract, by name.

    A :class:`Mechanism` without direct-kinematics back ends (a bare
    :class:`~imagespace.core.planar.PlanarMechanism`, say) is refused with a TypeError that names
    what is missing and what to use instead; so is a mechanism of the other image space where
    the caller works in one (the planar engines take planar mechanisms).

    Parameters
    ----------
    value : object
    name : str
        The parameter's name in the messages.
    image_space : {"planar", "study"} or None
        The image space the caller works in (None: either).

    Raises
    ------
    TypeError
        ``value`` is not a :class:`Mechanism`, its back ends are incomplete, or it lives in
        another image space than ``image_space``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.core.mechanism import check_mechanism
    >>> check_mechanism(isp.examples.general_3rpr()).name
    'general 3-RPR'
    >>> from imagespace.core.planar import PlanarMechanism
    >>> check_mechanism(PlanarMechanism(isp.examples.general_3rpr().legs))
    Traceback (most recent call last):
    ...
    imagespace.exceptions.InputTypeError: manipulator must be a mechanism with direct-kinematics back ends; PlanarMechanism ... lacks solve, ...
    """
    if not isinstance(value, Mechanism):
        want = ("a PlanarParallel (a planar imagespace Mechanism, e.g. isp.examples.general_3rpr())"
                if image_space == "planar" else
                "a GoughStewart or a ThreeRPS (a spatial imagespace Mechanism)" if image_space == "study" else
                "an imagespace Mechanism (a PlanarParallel such as isp.examples.general_3rpr(), a "
                "GoughStewart or a ThreeRPS)")
        raise InputTypeError(f"{name} must be {want}, got {type(value).__name__} {value!r:.80}")
    if image_space is not None and value.image_space != image_space:
        want = ("a PlanarParallel (a planar mechanism, e.g. isp.examples.general_3rpr())"
                if image_space == "planar" else "a spatial platform (GoughStewart, ThreeRPS)")
        raise InputTypeError(f"{name} must be {want}, got the {value.image_space or 'unknown'} mechanism "
                             f"{type(value).__name__} {value.name!r}")
    be = value.backends
    missing = list(BACKEND_STAGES) if be is None else be.missing()
    if missing:
        hint = (" (a PlanarMechanism holds the derivations only: build an isp.PlanarParallel from "
                "the same legs)" if type(value).__name__ == "PlanarMechanism" else "")
        raise InputTypeError(f"{name} must be a mechanism with direct-kinematics back ends; "
                             f"{type(value).__name__} {value.name!r} lacks {', '.join(missing)}{hint}")
    return value


def index_rows(result: Any, i: Any, row: Callable[[int], Any]) -> Any:
    """``result[i]`` of a batch result of any mechanism: ``row(k)`` for an integer ``i``
    (negative from the end), a list of them for a slice.

    Raises
    ------
    IndexError
        ``i`` is out of range.
    TypeError
        ``i`` is not an integer or a slice.

    Examples
    --------
    >>> from imagespace.core.mechanism import index_rows
    >>> index_rows([10, 20, 30], -1, lambda k: k), index_rows([10, 20, 30], slice(None, None, -2), lambda k: k)
    (2, [2, 0])
    """
    n = len(result)
    if isinstance(i, slice):
        return [row(k) for k in range(*i.indices(n))]
    if isinstance(i, (bool, np.bool_)) or not isinstance(i, (int, np.integer)):
        raise InputTypeError(f"a batch result is indexed by a row number or a slice, got {type(i).__name__} {i!r:.40}")
    k = int(i) + (n if i < 0 else 0)
    if not 0 <= k < n:
        raise RowIndexError(f"row {int(i)} is out of range for a batch of {n} rows (valid: -{n}..{n - 1})")
    return row(k)
