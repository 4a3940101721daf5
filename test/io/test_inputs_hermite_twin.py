"""EndPoseInput.attachment_at evaluates its cubic Hermite per component in plain floats; the values
must be those of the 3-vector formula (numpy, the same operations in the same order) to the last bit,
on a jittered stream with an offset attachment, a turning body and twists on some knots."""

import math

import numpy as np

from tether_sim.io.inputs import EndPoseInput


def _vector_formula(inp, t):
    """The Hermite interpolation on numpy 3-vectors (inside the samples)."""
    s = inp._samples
    i = inp._bracket(t)
    a, b = s[i], s[i + 1]
    h = b.stamp - a.stamp
    u = (t - a.stamp) / h
    m0, m1 = inp._knot_velocity(i) * h, inp._knot_velocity(i + 1) * h
    h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
    d00, d10, d01, d11 = 6 * u**2 - 6 * u, 3 * u**2 - 4 * u + 1, -6 * u**2 + 6 * u, 3 * u**2 - 2 * u
    pos = h00 * a.attachment + h10 * m0 + h01 * b.attachment + h11 * m1
    vel = (d00 * a.attachment + d10 * m0 + d01 * b.attachment + d11 * m1) / h
    return pos, vel


def test_plain_float_hermite_equals_the_vector_formula():
    rng = np.random.default_rng(11)
    inp = EndPoseInput("ship", (1.5, -0.4, 2.0), min_spacing=0.01)
    t = 0.0
    for k in range(300):
        t += 0.02 + rng.normal() * 0.002
        psi = 0.3 * math.sin(0.7 * t)
        p = (2.0 * math.cos(1.2 * t), 0.5 * math.sin(0.4 * t), 2.0 * math.sin(1.2 * t))
        assert inp.add_pose(t, p, (0.0, 0.0, math.sin(psi / 2), math.cos(psi / 2))) is None
        if k % 7 == 0:
            assert inp.add_twist(t, (-2.4 * math.sin(1.2 * t), 0.2 * math.cos(0.4 * t), 2.4 * math.cos(1.2 * t)),
                                 (0.0, 0.0, 0.21 * math.cos(0.7 * t))) is None
    stamps = inp._stamps
    for q in rng.uniform(stamps[0], stamps[-1], 500):
        if q in stamps:
            continue
        p, v = inp.attachment_at(q)
        p_ref, v_ref = _vector_formula(inp, q)
        assert p.tolist() == p_ref.tolist() and v.tolist() == v_ref.tolist()
