"""The error metrics of the real-scene suite (issue 12), on luminance
Y = 0.2126 R + 0.7152 G + 0.0722 B of (n, 3) values y against a reference r:

    NRMSE                          sqrt(mean((y - r)^2)) / mean(r)
    weighted relative RMSE         sqrt(sum((y - r)^2 / r) / sum(r)) over points with
                                   r > 1% of mean(r) (the points the reference sees lit)
    bias                           mean(y) / mean(r) - 1

The reference's own noise (its NRMSE) is removed in quadrature where stated:
sqrt(max(e^2 - noise^2, 0)). Plain numpy, no Blender.
"""

import numpy

LUMINANCE = numpy.array([0.2126, 0.7152, 0.0722])


def luminance(values):
    return numpy.asarray(values, dtype=numpy.float64).reshape(-1, 3) @ LUMINANCE


def nrmse(values, reference):
    y, r = luminance(values), luminance(reference)
    return float(numpy.sqrt(numpy.mean((y - r) ** 2)) / numpy.mean(r))


def weighted_relative_rmse(values, reference):
    y, r = luminance(values), luminance(reference)
    lit = r > 0.01 * numpy.mean(r)
    return float(numpy.sqrt(numpy.sum((y[lit] - r[lit]) ** 2 / r[lit]) / numpy.sum(r[lit])))


def without_noise(error, noise):
    return float(numpy.sqrt(max(error * error - noise * noise, 0.0)))


def row_metrics(metrics, reference_samples, reference_noise):
    """The fields of compare_at_subset's figures that every study's rows carry."""
    return {
        "reference_samples": reference_samples, "reference_noise": reference_noise,
        "nrmse": metrics["nrmse"],
        "nrmse_without_reference_noise": metrics["nrmse_without_reference_noise"],
        "weighted_relative_rmse": metrics["weighted_relative_rmse"],
        "bias": metrics["bias"], "worst_objects": metrics["per_object"][:3],
    }


def compare_at_subset(values, reference, reference_noise, object_names):
    """The suite's figures for one method at the subset; per object (names per point) the
    NRMSE, the bias and the share of the squared error, largest share first."""
    y, r = luminance(values), luminance(reference)
    error = nrmse(values, reference)
    per_object = []
    total = float(numpy.sum((y - r) ** 2)) or 1.0
    for name in sorted(set(object_names)):
        mask = object_names == name
        if mask.sum() < 5 or not (numpy.mean(r[mask]) > 0.0):
            continue
        per_object.append({
            "object": str(name), "points": int(mask.sum()),
            "nrmse": float(numpy.sqrt(numpy.mean((y[mask] - r[mask]) ** 2)) / numpy.mean(r[mask])),
            "bias": float(numpy.mean(y[mask]) / numpy.mean(r[mask]) - 1.0),
            "error_share": float(numpy.sum((y[mask] - r[mask]) ** 2) / total),
        })
    per_object.sort(key=lambda o: -o["error_share"])
    return {
        "nrmse": error,
        "nrmse_without_reference_noise": without_noise(error, reference_noise),
        "weighted_relative_rmse": weighted_relative_rmse(values, reference),
        "bias": float(numpy.mean(y) / numpy.mean(r) - 1.0),
        "finite": bool(numpy.isfinite(values).all()),
        "per_object": per_object,
    }
