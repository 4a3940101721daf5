"""Signal analysis helpers of tether_sim.scenarios.harness on synthetic signals (no solver)."""

import numpy as np
import pytest

from tether_sim.scenarios import harness


def test_crossing_time_interpolates_the_first_rising_crossing():
    t = np.linspace(0, 10, 1001)
    y = np.tanh((t - 4.0) / 0.3)
    assert harness.crossing_time(t, y, 0.0) == pytest.approx(4.0, abs=1e-6)
    assert np.isnan(harness.crossing_time(t, y, 2.0))
    y2 = np.sin(2 * np.pi * t / 4.0)  # rising zero crossings at 0 (excluded: starts at 0), 4, 8
    assert harness.crossing_time(t, y2, 0.0, after=1.0) == pytest.approx(4.0, abs=1e-3)


def test_period_and_dominant_frequency_of_a_noisy_sine():
    t = np.arange(0, 40, 0.01)
    f0 = 0.731
    rng = np.random.default_rng(1)
    y = np.cos(2 * np.pi * f0 * t + 0.3) + 0.05 * np.cos(2 * np.pi * 5.1 * t) + 1e-3 * rng.standard_normal(t.size)
    assert harness.dominant_frequency(t, y) == pytest.approx(f0, rel=1e-4)
    assert harness.period_from_crossings(t, np.cos(2 * np.pi * f0 * t + 0.3)) == pytest.approx(1 / f0, rel=1e-4)
    f, Y = harness.amplitude_spectrum(t, np.cos(2 * np.pi * 2.0 * t))
    assert f[np.argmax(Y)] == pytest.approx(2.0) and Y.max() == pytest.approx(1.0, rel=1e-3)


def test_sag_below_chord():
    x = np.linspace(0, 10, 101)
    z = 2.0 + 0.3 * x - 0.1 * x * (10 - x)  # inclined chord from (0, 2) to (10, 5) plus a parabola
    r = np.stack([x, np.zeros_like(x), z], axis=1)
    assert harness.sag_below_chord(r) == pytest.approx(2.5)
