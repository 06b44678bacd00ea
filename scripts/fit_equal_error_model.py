#!/usr/bin/env python3
"""Fits a cost and variance model to an equal-error CSV of `vx bench render --sections
equal-error` (tools/bench_render_equal_error.cpp) and asks what the shadows + reflections row's
fixed counts could reach at best (docs/render_report.md, stop 28).

Model, over the raw fixed-count rows of one feature set (spp n0 at the first hit, bounce spp nb
at every bounce hit):
    variance  = P * n0^-alpha + B * nb^-beta          (RMSE^2; the two estimators are independent)
    frame ms  = T0 + a * n0 + b * nb
alpha and beta by a grid search, P and B by least squares of relative error (weights 1 / var^2),
T0, a and b by least squares. Then the cheapest (n0, nb), continuous, whose modelled variance is
at most the target's, and the frame time that needs beside the thesis's ratio to the flat row.

Usage: fit_equal_error_model.py DIR/equal_error.csv [--set shadows+reflections] [--ratio 19.12]
Needs numpy (Debian: python3-numpy). Prints the fit, its worst residuals and the optimum.
"""
import argparse
import csv
import sys

import numpy as np


def load(path, feature_set):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["feature_set"] != feature_set or r["denoise"] != "0" or r["light_cache"] != "0":
                continue
            if r.get("by_weight", "0") != "0":
                continue
            rows.append((float(r["spp"]), float(r["bounce_spp"]), float(r["frame_ms"]), float(r["rmse"]),
                         float(r["target_rmse"]), float(r["flat_ms"])))
    return np.array(rows)


def fit_variance(n0, nb, var):
    best = None
    for alpha in np.arange(0.8, 2.01, 0.05):
        for beta in np.arange(0.8, 2.01, 0.05):
            m = np.stack([n0 ** -alpha, nb ** -beta], axis=1) / var[:, None]
            coef, *_ = np.linalg.lstsq(m, np.ones_like(var), rcond=None)
            if np.any(coef <= 0):
                continue
            rel = (np.stack([n0 ** -alpha, nb ** -beta], axis=1) @ coef) / var - 1.0
            err = float(np.sqrt(np.mean(rel ** 2)))
            if best is None or err < best[0]:
                best = (err, alpha, beta, coef)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--set", default="shadows+reflections")
    ap.add_argument("--ratio", type=float, default=19.12, help="the thesis's ratio to the flat row")
    args = ap.parse_args()
    d = load(args.csv, args.set)
    if len(d) < 5:
        sys.exit(f"{args.csv}: {len(d)} raw fixed-count rows of '{args.set}' (need 5 or more)")
    n0, nb, ms, rmse, target, flat = d.T
    nb = np.where(nb > 0, nb, 1.0)  # Without reflections the bounce term is 0 samples: fit P alone.
    var, v_target, flat_ms = rmse ** 2, target[0] ** 2, flat[0]
    fit = fit_variance(n0, nb, var)
    if fit is None:
        sys.exit("no fit with positive terms")
    err, alpha, beta, (p, b_var) = fit
    t, *_ = np.linalg.lstsq(np.stack([np.ones_like(n0), n0, nb], axis=1), ms, rcond=None)
    t0, a, b = t
    model_ms = t0 + a * n0 + b * nb
    print(f"{len(d)} rows of {args.set}; flat {flat_ms:.3f} ms; target RMSE {target[0]:.5f}")
    print(f"variance = {p:.3e} n0^-{alpha:.2f} + {b_var:.3e} nb^-{beta:.2f}   (relative RMS residual {err:.1%})")
    print(f"frame ms = {t0:.2f} + {a:.3f} n0 + {b:.3f} nb   (largest residual {np.max(np.abs(model_ms - ms)):.2f} ms)")
    # The cheapest continuous (n0, nb) on the target's variance: a dense search along n0.
    best = None
    for x in np.linspace(1.0, 256.0, 20001):
        rest = v_target - p * x ** -alpha
        if rest <= 0:
            continue
        y = max((b_var / rest) ** (1.0 / beta), 1.0)
        cost = t0 + a * x + b * y
        if best is None or cost < best[0]:
            best = (cost, x, y)
    cost, x, y = best
    budget = args.ratio * flat_ms
    print(f"cheapest on the model at the target: n0 {x:.1f}, nb {y:.1f}: {cost:.2f} ms = {cost / flat_ms:.1f}x flat")
    print(f"the thesis's {args.ratio}x is {budget:.2f} ms: sample costs (a, b) would have to fall "
          f"{(cost - t0) / max(budget - t0, 1e-9):.2f}x with T0 as it is, or every cost {cost / budget:.2f}x")


if __name__ == "__main__":
    main()
