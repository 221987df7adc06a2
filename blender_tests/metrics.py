"""Error metric of DESIGN.md, free of bpy so it runs in plain Python and inside Blender.

Relative RMSE, luminance weighted, over bake points:

    e = sqrt( sum_i sum_c w_c (v_ic - r_ic)^2  /  sum_i sum_c w_c r_ic^2 )

with Rec. 709 luminance weights w = (0.2126, 0.7152, 0.0722): a channel
counts as much as the eye weighs it, and the error is relative to the
reference's energy, so a scene's exposure does not change it.
"""

import numpy

REC709_LUMINANCE = numpy.array([0.2126, 0.7152, 0.0722])


def relative_rmse(values, reference):
    """Luminance-weighted relative RMSE of (n, 3) `values` against (n, 3) `reference`."""
    v = numpy.asarray(values, dtype=numpy.float64).reshape(-1, 3)
    r = numpy.asarray(reference, dtype=numpy.float64).reshape(-1, 3)
    if v.shape != r.shape:
        raise ValueError(f"shape mismatch: {v.shape} vs {r.shape}")
    denominator = float(((r * r) @ REC709_LUMINANCE).sum())
    if denominator <= 0.0:
        raise ValueError("reference is black: relative error undefined")
    return float(numpy.sqrt((((v - r) ** 2) @ REC709_LUMINANCE).sum() / denominator))


def noise_from_halves(half_a, half_b):
    """Relative RMSE noise of the average of two independent estimates, from their difference.

    If each half has noise sigma (same metric), their difference has sqrt(2) sigma
    and their average sigma / sqrt(2); so the average's noise is e(a, b) / 2.
    """
    return 0.5 * relative_rmse(half_a, half_b)


def luminance(values):
    return numpy.asarray(values, dtype=numpy.float64).reshape(-1, 3) @ REC709_LUMINANCE
