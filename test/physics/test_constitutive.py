"""Tension-strain laws [PE2020 Eq. 22] and their slopes."""

import numpy as np
import pytest

from tether_sim.physics.cable import CableProperties
from tether_sim.physics.constitutive import TensionLaw


def test_bilinear_never_compresses_and_damps_only_when_taut():
    law = TensionLaw(CableProperties(EA=1000.0, damping=50.0, material="bilinear"))
    assert law.tension(-0.01, 0.0)[0] == 0.0
    assert law.tension(-0.01, 5.0)[0] == 0.0  # slack: no tension even while stretching
    assert law.tension(0.01, 0.0)[0] == pytest.approx(10.0)
    assert law.tension(0.01, 0.1)[0] == pytest.approx(15.0)
    assert law.tension(0.01, -1.0)[0] == 0.0  # fast slackening: clipped, never pushes
    assert law.slope(-0.1)[0] == 0.0 and law.slope(0.1)[0] == 1000.0


def test_linear_law_allows_compression():
    law = TensionLaw(CableProperties(EA=1000.0, damping=50.0, material="linear"))
    assert law.tension(-0.01, 0.02)[0] == pytest.approx(-10.0 + 1.0)
    assert law.slope(-0.5)[0] == 1000.0


def test_table_law_interpolates_extrapolates_and_inverts():
    cab = CableProperties(material="table", table_strain=(0.0, 0.01, 0.03), table_tension=(0.0, 100.0, 500.0), damping=0.0)
    law = TensionLaw(cab)
    assert law.tension(0.005)[0] == pytest.approx(50.0)
    assert law.tension(0.02)[0] == pytest.approx(300.0)
    assert law.tension(0.04)[0] == pytest.approx(700.0)  # last slope 2e4 N
    assert law.tension(-0.01)[0] == 0.0
    assert law.slope(0.02)[0] == pytest.approx(2e4) and law.max_slope() == pytest.approx(2e4)
    for T in (10.0, 300.0, 900.0):
        assert law.tension(law.strain_at(T))[0] == pytest.approx(T)


def test_bad_table_is_rejected_with_the_key_name():
    with pytest.raises(ValueError, match="table_strain"):
        TensionLaw(CableProperties(material="table", table_strain=(0.0, 0.02, 0.01), table_tension=(0.0, 1.0, 2.0)))
    with pytest.raises(ValueError, match="table_strain"):
        TensionLaw(CableProperties(material="table", table_strain=(0.0,), table_tension=(0.0,)))


def test_vectorised_output_shape():
    law = TensionLaw(CableProperties(EA=10.0))
    assert law.tension(np.linspace(0, 1, 5)).shape == (5,)
