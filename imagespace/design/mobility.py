"""Mobility by the Grübler-Kutzbach count.

``M = D (n - p - 1) + sum f_i`` with ``n`` links (the ground included), ``p`` joints of
freedoms ``f_i`` and ``D = 3`` (planar) or ``6`` (spatial); ``M <= 0`` is a structure
(seed 003).

Where the count fails: it only counts, it does not look at the geometry. Overconstrained
mechanisms (Bennett's 4R linkage, parallel-axis planar loops treated as spatial, many spatial
parallel mechanisms with special joint directions) move although ``M <= 0``; singular
configurations can give extra freedoms; redundant joints count twice. The real test is the rank of
the mechanism's constraint or twist system (the screw theory of :mod:`imagespace` [6/7]); the
Grübler number is a lower bound on the mobility of a generic member of the family.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

from .._validate import _short, as_count, as_flag
from ..exceptions import InputError, InputTypeError
from ..core.mechanism import check_mechanism

__all__ = ["Mobility", "gruebler", "mechanism_mobility", "manipulator_mobility", "JOINT_FREEDOMS"]

JOINT_FREEDOMS = {"R": 1, "P": 1, "H": 1, "C": 2, "U": 2, "S": 3, "E": 3}
"""Freedoms of the usual lower pairs (revolute, prismatic, helical, cylindrical, universal,
spherical, planar)."""


@dataclass(frozen=True)
class Mobility:
    """A Grübler-Kutzbach count.

    Attributes
    ----------
    M : int
    D : int
        3 (planar) or 6 (spatial).
    n, p : int
        Links (ground included) and joints.
    freedoms : int
        ``sum f_i``.
    kind : str
        ``"mechanism"`` (``M > 0``) or ``"structure"`` (``M <= 0``; ``M < 0``: statically
        indeterminate / overconstrained by the count).
    """

    M: int
    D: int
    n: int
    p: int
    freedoms: int
    kind: str

    def __int__(self):
        return self.M


def _int(v, name, minimum=0):
    return as_count(v, name, minimum)


def _sequence(v, name, what):
    if v is None or isinstance(v, (bytes, numbers.Number)) or not hasattr(v, "__iter__"):
        raise InputTypeError(f"{name} must be {what}, got {type(v).__name__} {_short(v)}")
    return list(v)


def gruebler(n, joints, D=3):
    """Grübler-Kutzbach mobility from counts.

    Parameters
    ----------
    n : int
        Number of links, the ground included.
    joints : sequence of int or str, or int
        The freedom of every joint (``1`` or ``"R"``, ``"P"``, ``3`` or ``"S"`` ...); an int means
        that many one-freedom joints.
    D : {3, 6}

    Returns
    -------
    Mobility

    Raises
    ------
    TypeError
        For a non-integer ``n`` or ``D``, or ``joints`` that is neither an int nor a sequence.
    InputError
        For ``D`` other than 3 or 6, an unknown joint, a joint with more freedoms than ``D``
        allows, or a negative count.

    Examples
    --------
    >>> from imagespace.design.mobility import gruebler
    >>> gruebler(8, 9).M                       # 3-RPR (seed 003)
    3
    >>> gruebler(4, "RRRR").M                  # a four-bar
    1
    >>> gruebler(8, "RPS" * 3, D=6).M          # 3-RPS
    3
    """
    if isinstance(D, (bool, float)) or not isinstance(D, numbers.Integral):
        raise InputTypeError(f"D must be the whole number 3 (planar) or 6 (spatial), got {type(D).__name__} {_short(D)}")
    if D not in (3, 6):
        raise InputError(f"D must be 3 (planar) or 6 (spatial), got {D!r}")
    _int(n, "n", 1)
    if isinstance(joints, numbers.Integral) and not isinstance(joints, bool):
        fs = [1] * _int(joints, "joints")
    else:
        fs = []
        for k, j in enumerate(_sequence(joints, "joints", "a number of joints or a sequence of joint "
                                        "letters/freedoms")):
            if isinstance(j, str):
                if j not in JOINT_FREEDOMS:
                    raise InputError(f"joints[{k}] = {j!r} is not a known joint; use one of "
                                     f"{sorted(JOINT_FREEDOMS)} or a number of freedoms")
                fs.append(JOINT_FREEDOMS[j])
            else:
                f = _int(j, f"joints[{k}]")
                if f > D - 1:
                    raise InputError(f"joints[{k}] has {f} freedoms, more than a joint can have in D = {D}")
                fs.append(f)
    M = D * (n - len(fs) - 1) + sum(fs)
    return Mobility(M, D, n, len(fs), sum(fs), "mechanism" if M > 0 else "structure")


def mechanism_mobility(links, joints, D=3):
    """Grübler-Kutzbach mobility from a description.

    Parameters
    ----------
    links : sequence of hashable
        Link names; the ground must be one of them.
    joints : sequence of (link_a, link_b, joint)
        ``joint``: a joint letter (``"R"``, ``"P"``, ``"S"``, ...) or a number of freedoms.
    D : {3, 6}

    Returns
    -------
    Mobility

    Raises
    ------
    TypeError
        For ``links``/``joints`` that are not sequences, an unhashable link name, or a non-integer
        ``D``.
    InputError
        A joint names an unknown link, joins a link to itself, or a link has no joint; no links,
        repeated names, a malformed joint entry, or an unknown joint type.

    Examples
    --------
    >>> from imagespace.design.mobility import mechanism_mobility
    >>> mechanism_mobility(["ground", "crank", "coupler", "rocker"],
    ...                    [("ground", "crank", "R"), ("crank", "coupler", "R"),
    ...                     ("coupler", "rocker", "R"), ("rocker", "ground", "R")]).M
    1
    """
    names = _sequence(links, "links", "a sequence of link names")
    if not names:
        raise InputError("links must name at least one link (the ground), got an empty sequence")
    for k, nm in enumerate(names):
        try:
            hash(nm)
        except TypeError:
            raise InputTypeError(f"links[{k}] must be a hashable name, got {type(nm).__name__} {_short(nm)}") from None
    if len(set(names)) != len(names):
        raise InputError("links must have distinct names")
    used = set()
    kinds = []
    for k, item in enumerate(_sequence(joints, "joints", "a sequence of (link_a, link_b, joint)")):
        try:
            a, b, j = item
        except (TypeError, ValueError):
            raise InputError(f"joints[{k}] must be (link_a, link_b, joint), got {item!r}") from None
        for end in (a, b):
            if end not in names:
                raise InputError(f"joints[{k}] names the unknown link {end!r}")
        if a == b:
            raise InputError(f"joints[{k}] joins {a!r} to itself")
        used |= {a, b}
        kinds.append(j)
    lonely = [nm for nm in names if nm not in used]
    if lonely and len(names) > 1:
        raise InputError(f"links {lonely} have no joint")
    return gruebler(len(names), kinds, D)


def manipulator_mobility(manipulator, locked=False):
    """Grübler-Kutzbach mobility of a planar 3-legged manipulator from its legs.

    Every leg of three one-freedom joints adds two links; base and platform are two more.

    Parameters
    ----------
    manipulator : PlanarParallel
    locked : bool
        Lock the actuated joints (a locked joint has no freedom): the result should be a
        structure (``M = 0``).

    Returns
    -------
    Mobility

    Raises
    ------
    TypeError
        For a ``manipulator`` that is not a PlanarParallel or a non-boolean ``locked``.

    Examples
    --------
    >>> import imagespace as isp
    >>> from imagespace.design.mobility import manipulator_mobility
    >>> m = isp.examples.choi_3ppr()
    >>> manipulator_mobility(m).M, manipulator_mobility(m, locked=True).M
    (3, 0)
    """
    check_mechanism(manipulator)
    locked = as_flag(locked, "locked")
    n = 2 + sum(len(leg.joints) - 1 for leg in manipulator.legs)
    fs = []
    for leg in manipulator.legs:
        for k, letter in enumerate(leg.joints):
            fs.append(0 if locked and k == leg.actuated else JOINT_FREEDOMS[letter])
    return gruebler(n, fs, D=3)
