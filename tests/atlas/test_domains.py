"""Aspects and uniqueness domains (Chablat & Wenger).

Independent checks: the direct kinematics (certified batch) restricted to a uniqueness domain has
exactly one solution at 1,200 sampled joint vectors of its image; a non-cuspidal design (similar
base and platform, no cusp by the literature and by is_cuspidal's proof) has its aspects as
uniqueness domains (Wenger, Robotica 25(6), 2007: a manipulator is non-cuspidal exactly when
its uniqueness domains are its aspects).

No test checks a published example's number of uniqueness domains: the examples of Wenger &
Chablat (arXiv:0705.0960, a 3-RPR) and Chablat, Moroz & Wenger (arXiv:1104.0840) could be read
only up to their abstracts and introductions here, without their anchors, joint limits or counts
(issue [17]; see imagespace/atlas/domains.py). The general 3-RPR test checks the qualitative claim
of arXiv:0705.0960's abstract instead: its aspects are not uniqueness domains.
"""

import numpy as np
import pytest
import sympy as sp
from scipy import ndimage

import imagespace as isp
from imagespace.atlas import uniqueness_domains
from imagespace.core.legs import RPR
from imagespace.exceptions import InputError


@pytest.fixture(scope="module")
def general():
    m = isp.examples.general_3rpr()
    return m, uniqueness_domains(m, [(8, 14), (2, 8), (7, 13)], (56, 56, 96))


@pytest.mark.slow
def test_direct_kinematics_restricted_to_a_domain_has_one_solution(general, rng):
    m, ud = general
    assert ud.n_aspects >= 2 and ud.n_domains > ud.n_aspects       # cuspidal: more domains than aspects
    total, boundary = 0, 0
    for k in range(ud.n_domains):
        mask = ud.domain_mask(k)
        deep = ndimage.binary_erosion(mask, structure=np.ones((3, 3, 3)))
        core = deep
        P = ud.poses(core)
        sel = P[rng.choice(len(P), min(400, len(P)), replace=False)]
        res = m.direct_kinematics_batch(m.inverse_kinematics(sel), certify=True)
        assert res.consistent.all()
        for i in range(len(sel)):
            modes = res.poses[i][res.valid[i]]
            own = np.max(np.abs(modes - sel[i]), axis=1) < 1e-7
            assert own.sum() == 1                                  # the sampled pose is a mode
            idx, inside = ud.locate(modes[~own])
            assert not np.any(inside & deep[idx[:, 0], idx[:, 1], idx[:, 2]])
            boundary += int(np.sum(inside & mask[idx[:, 0], idx[:, 1], idx[:, 2]]))
            total += 1
    assert total >= 1000
    assert boundary <= 0.02 * total                               # within a cell of the domain's edge


@pytest.mark.slow
def test_non_cuspidal_design_has_its_aspects_as_uniqueness_domains():
    base, scale = ((0, 0), (10, 0), (3, 8)), sp.Rational(1, 2)
    m = isp.PlanarParallel([RPR(base=b, platform=(scale * b[0], scale * b[1])) for b in base])
    ud = uniqueness_domains(m, [(3, 9), (3, 9), (3, 9)], 48)
    assert ud.n_aspects >= 2
    assert ud.n_domains == ud.n_aspects
    for k in range(ud.n_domains):
        a = ud.domain_aspect[k]
        assert ud.domain_mask(k).sum() >= 0.95 * (ud.aspect == a).sum()
    # each domain is one basic region with a single preimage in its aspect
    assert all(len(d) == 1 and ud.region_preimages[d[0]] == 1 for d in ud.domains)


@pytest.mark.slow
def test_validation_and_figure(general):
    m, ud = general
    with pytest.raises(InputError, match="resolution must be at most 200"):
        uniqueness_domains(m, [(8, 14), (2, 8), (7, 13)], 300)
    with pytest.raises(InputError, match="joint_box"):
        uniqueness_domains(m, [(8, 14), (2, 8)], 20)
    with pytest.raises(TypeError, match="ud must be a UniquenessDomains"):
        isp.atlas.plot_uniqueness_domains("ud")
    fig = ud.figure()
    assert len(fig.axes) == 2 * ud.n_domains
