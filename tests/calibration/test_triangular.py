"""Farago et al. (IEEE Access): the 9-parameter lower-triangular model and its solvers."""

from pathlib import Path

import numpy as np
import pytest

from app.calibration.shared.errors import CalibrationError, InsufficientDataError
from app.calibration.still.fixed_point import div_round, fixed_point_descent, format_for
from app.calibration.still.triangular import (
    TriangularCalibration,
    alpha_vector,
    fit_triangular,
    gradient_descent,
    k_matrix,
)
from simulations.triangular import simulate_scenario, uncalibrate

DATA = Path(__file__).resolve().parents[1] / "data"
G = 9.80665


def table(k: int) -> np.ndarray:
    return np.loadtxt(DATA / f"000_table{k}.csv", delimiter=",", skiprows=2)[:, 1:]


P_TRUE = np.array([1.04, 0.97, 1.02, 0.03, -0.02, 0.04, 0.05, -0.06, 0.08])


def exact_points(n=18, seed=1):
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, 3))
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    return uncalibrate(P_TRUE, a)


def test_model_is_eqs_7_to_9():
    v = np.array([[0.3, -0.8, 0.5]])
    cal = TriangularCalibration(
        K=k_matrix(P_TRUE), o=P_TRUE[6:], gravity=1.0, means=v, solver="lm", covariance=None, dof=0
    )
    kxx, kyy, kzz, kxy, kxz, kyz, ox, oy, oz = P_TRUE
    vx, vy, vz = v[0]
    expected = [
        kxx * (vx + ox),
        kxy * (vx + ox) + kyy * (vy + oy),
        kxz * (vx + ox) + kyz * (vy + oy) + kzz * (vz + oz),
    ]
    np.testing.assert_allclose(cal.apply(v)[0], expected, rtol=1e-14)
    np.testing.assert_allclose(cal.p, P_TRUE)


def test_lm_recovers_exact_parameters_in_any_unit():
    v = exact_points()
    cal_g = fit_triangular(v, gravity=1.0)
    np.testing.assert_allclose(cal_g.p, P_TRUE, atol=1e-10)
    cal_si = fit_triangular(v * G, gravity=G)
    np.testing.assert_allclose(cal_si.K, cal_g.K, atol=1e-10)
    np.testing.assert_allclose(cal_si.o, cal_g.o * G, atol=1e-9)
    assert cal_si.ok and cal_si.metrics["norm_error_max"] < 1e-10
    assert np.allclose(np.triu(cal_si.K, 1), 0.0)


def test_descents_as_published():
    v = exact_points()
    p, its = gradient_descent(v)
    assert its == 50
    # 50 iterations of the published descent get close to, not onto, the optimum.
    np.testing.assert_allclose(p, P_TRUE, atol=3e-3)
    # Run long, it converges to the minimum of the forward-difference gradient, which sits
    # O(h) = O(1e-5) from the true minimum.
    p500, _ = gradient_descent(v, max_iter=2000)
    np.testing.assert_allclose(p500, P_TRUE, atol=3e-5)
    # 32-bit fixed point follows the float descent to a few LSB-level differences.
    run32 = fixed_point_descent(v, bits=32, h=1e-5, alphas=alpha_vector())
    np.testing.assert_allclose(run32.p, p, atol=2e-5)
    assert run32.q_format == "Q7.24" and run32.h == 168 / 2**24
    # 16-bit: h = 0.01 (41 LSB of Q3.12).  The forward difference moves the stationary point by
    # −(h/2) H⁻¹ diag(H) to first order (H the Hessian of the cost), up to 0.017 here; the 16-bit
    # run lands within a few LSB of the float descent run with the same h.
    run16 = fixed_point_descent(v, bits=16, h=0.01, alphas=alpha_vector())
    assert run16.q_format == "Q3.12" and run16.h == 41 / 4096
    p16f, _ = gradient_descent(v, h=41 / 4096)
    np.testing.assert_allclose(run16.p, p16f, atol=4 / 4096)
    np.testing.assert_allclose(run16.p, P_TRUE, atol=0.02)
    assert not run16.saturated and not run32.saturated


@pytest.mark.parametrize("solver", ["lm", "gradient", "fixed16", "fixed32"])
def test_solvers_on_000_dataset_1(solver):
    m = table(1)
    cal = fit_triangular(m[:20], gravity=9.806, solver=solver)
    assert cal.ok, cal.reasons
    held = cal.evaluate(m[20:])
    assert held["error_after_mg"] < held["error_before_mg"] / 5
    assert cal.metrics["solver"] == solver
    u = cal.uncertainty()
    assert np.array(u["K"]).shape == (3, 3) and len(u["o"]) == 3
    assert np.allclose(np.triu(np.array(u["K"]), 1), 0.0)


def test_lm_is_best_on_the_objective():
    m = table(1)[:20]
    costs = {s: fit_triangular(m, gravity=9.806, solver=s).metrics["cost_12"] for s in ("lm", "gradient", "fixed16")}
    assert costs["lm"] <= costs["gradient"] * 1.05 and costs["lm"] < costs["fixed16"]


def test_near_duplicate_and_coverage_warnings_dataset_3():
    cal = fit_triangular(table(3)[2:23], gravity=9.806)
    dup = [w for w in cal.warnings if "near-duplicate" in w]
    assert len(dup) == 1 and "readings 0 and 18" in dup[0]
    assert any("poor coverage" in w and "+y" in w for w in cal.warnings)


def test_intervals_cover_truth_in_simulation():
    rng = np.random.default_rng(77)
    hits = total = 0
    for _ in range(150):
        sc = simulate_scenario(rng, noise_g=0.003)
        cal = fit_triangular(sc.points, gravity=1.0)
        u = cal.uncertainty()
        K = np.array(u["K"])
        hw = np.r_[K[0, 0], K[1, 1], K[2, 2], K[1, 0], K[2, 0], K[2, 1], u["o"]]
        hits += int(np.sum(np.abs(cal.p - sc.p) <= hw))
        total += 9
    assert 0.92 <= hits / total <= 0.98


def test_dict_round_trip():
    cal = fit_triangular(table(2)[:20], gravity=9.806, solver="fixed16")
    d = cal.to_dict()
    assert d["model"]["type"] == "triangular" and set(d["model"]) == {"type", "K", "o"}
    back = TriangularCalibration.from_dict(d)
    assert back.solver == "fixed16"
    np.testing.assert_allclose(back.apply(table(2)), cal.apply(table(2)))
    np.testing.assert_allclose(back.uncertainty()["o"], cal.uncertainty()["o"])


def test_bad_inputs():
    m = table(1)[:20]
    with pytest.raises(InsufficientDataError, match="at least 9"):
        fit_triangular(m[:8], gravity=9.806)
    bad = m.copy()
    bad[2, 0] = np.nan
    with pytest.raises(CalibrationError, match="row 2"):
        fit_triangular(bad, gravity=9.806)
    with pytest.raises(InsufficientDataError, match="distinct"):
        fit_triangular(np.tile(m[0], (12, 1)), gravity=9.806)
    with pytest.raises(CalibrationError, match="unknown solver"):
        fit_triangular(m, gravity=9.806, solver="adam")


def test_one_hemisphere_is_not_ok():
    m = table(1)
    upper = m[m[:, 2] > 0.5]
    upper = np.vstack([upper, upper[:4] + [0.5, -0.5, 0.0]])
    for solver in ("lm", "gradient"):
        cal = fit_triangular(upper, gravity=9.806, solver=solver)
        assert not cal.ok
        assert any("one hemisphere" in r for r in cal.reasons)


# --- the fixed-point scheme of app/calibration/still/fixed_point.py, checked independently ---------


def test_fixed_point_primitives():
    q = format_for(16)
    assert (q.bits, q.frac, q.name) == (16, 12, "Q3.12")
    assert q.quantize(0.5 / 4096).item() == 1  # half an LSB rounds up
    assert q.quantize(-0.5 / 4096).item() == 0  # round half up, not away from zero
    assert q.quantize(-1.5 / 4096).item() == -1
    assert q.quantize(100.0).item() == 32767 and q.quantize(-100.0).item() == -32768
    assert q.quantize(0.01).item() == 41
    assert q.mul(4096, 4096).item() == 4096
    assert q.mul(3, 2048).item() == 2  # 1.5 LSB → 2 (half up)
    assert q.mul(-3, 2048).item() == -1  # −1.5 LSB → −1 (half up)
    assert q.mul(32767, 32767).item() == 32767  # saturates
    assert div_round(5, 2) == 3 and div_round(-5, 2) == -2 and div_round(7, 3) == 2
    assert format_for(32).name == "Q7.24" and format_for(32).quantize(1e-5).item() == 168


def _reference_run(points, bits, frac, h, alphas, iters):
    """A plain-integer transcription of the documented scheme (no numpy), for a few iterations."""
    lo, hi = -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    lo2, hi2 = -(1 << (2 * bits - 1)), (1 << (2 * bits - 1)) - 1

    def sat(x):
        return min(max(x, lo), hi)

    def sat2(x):
        return min(max(x, lo2), hi2)

    import math

    def qz(x):
        return sat(math.floor(x * (1 << frac) + 0.5))

    def mul(x, y):
        return sat((x * y + (1 << (frac - 1))) >> frac)

    def dv(n, d):
        return (2 * n + d) // (2 * d)

    V = [[qz(c) for c in row] for row in points]
    P = [qz(c) for c in (1, 1, 1, 0, 0, 0, 0, 0, 0)]
    hq = qz(h)
    A = [qz(a) for a in alphas]

    def cost(P):
        kxx, kyy, kzz, kxy, kxz, kyz, ox, oy, oz = P
        acc = 0
        for vx, vy, vz in V:
            wx, wy, wz = sat(vx + ox), sat(vy + oy), sat(vz + oz)
            ax = mul(kxx, wx)
            ay = sat(mul(kxy, wx) + mul(kyy, wy))
            az = sat(sat(mul(kxz, wx) + mul(kyz, wy)) + mul(kzz, wz))
            r = sat(sat(sat(mul(ax, ax) + mul(ay, ay)) + mul(az, az)) - (1 << frac))
            acc = sat2(acc + r * r)
        return dv(acc, len(V))

    for _ in range(iters):
        f0 = cost(P)
        grads = []
        for i in range(9):
            T = list(P)
            T[i] = sat(T[i] + hq)
            grads.append(sat(dv(sat2(cost(T) - f0), hq)))
        P = [sat(P[i] - mul(A[i], grads[i])) for i in range(9)]
    return P


@pytest.mark.parametrize("bits,frac,h", [(16, 12, 0.01), (32, 24, 1e-5)])
def test_fixed_point_descent_is_bit_exact(bits, frac, h):
    v = exact_points(n=12, seed=4) + np.random.default_rng(4).normal(scale=0.002, size=(12, 3))
    alphas = alpha_vector()
    ref = _reference_run(v.tolist(), bits, frac, h, alphas.tolist(), iters=5)
    run = fixed_point_descent(v, bits=bits, h=h, alphas=alphas, max_iter=5)
    assert run.p_raw.tolist() == ref


def test_descents_report_their_distance_to_the_optimum():
    m = table(1)[:20]
    assert "distance_to_lm" not in fit_triangular(m, gravity=9.806).metrics
    cal16 = fit_triangular(m, gravity=9.806, solver="fixed16")
    assert cal16.metrics["distance_to_lm"] > 1.0
    assert any("fixed16 solver stopped" in w for w in cal16.warnings)
    assert cal16.ok  # a warning, not a gate failure
    cal32 = fit_triangular(m, gravity=9.806, solver="fixed32")
    assert cal32.metrics["distance_to_lm"] < 1.0
