"""What the terminal shows: each command's summary of a body (the verdict first), the autocal folder's table
and the progress bar."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import numpy as np

from app.calibration.shared.angles import degrees_text, tilt_error_deg
from app.calibration.shared.orientations import WITHIN_LABEL_ANGLE
from app.calibration.shared.result import NormErrors
from app.cli.options import NOTES_SHOWN
from app.io.plural import counted
from app.words import render, render_body

if TYPE_CHECKING:
    from app.workflows.calibration import Calibration


def print_notes(notes, verbose: bool = False) -> None:
    """A calibration's notes (its warnings), each once: at most :data:`NOTES_SHOWN` lines unless ``verbose``, with
    a line that says how many more there are and how to see them."""
    unique = list(dict.fromkeys(notes or []))
    shown = unique if verbose else unique[:NOTES_SHOWN]
    for w in shown:
        print(f"warning: {w}")
    if len(unique) > len(shown):
        more = len(unique) - len(shown)
        print(f"({more} more note{'s' if more > 1 else ''}: --verbose shows {'them' if more > 1 else 'it'})")


def print_summary(calibration: Calibration, body: dict, recording: dict, verbose: bool = False) -> None:
    """What ``trical calibrate`` prints of a calibration (typed, and its plain form as answered and stored):
    what the recording held, the verdict, what each file gave, the model, the figures and the notes."""
    body = render_body(body, "cli")
    flight = body.get("flight")  # a compass from a flight: the log's facts, and no still segments read
    _print_source(body, recording, flight)
    if body.get("id"):
        print(f"calibration {body['id']} ({body['method']}), ok = {body['ok']}")
    print_verdict(body)
    if recording.get("parts"):
        _print_parts(body, recording)
    print_model(body["model"], per_sensor=calibration.result.PER_SENSOR)
    _print_figures(body)
    if flight and flight.get("compasses"):
        print_compasses(flight)
    for a in body.get("advice") or []:
        print(f"next pose: {a['words']} (shrinks the parameters' generalized variance by {100 * a['gain']:.0f} %)")
    print_notes(body["warnings"], verbose)


def _print_source(body: dict, recording: dict, flight: dict | None) -> None:
    """A flight's log and compass, or the still segments of the recording and those used."""
    if flight:
        print(
            f"{flight['generation']}: compass {flight['instance']}, {body['metrics']['n_samples']} samples "
            f"({flight['raw_how']}), attitude from {flight['attitude_source']}"
        )
        return
    rate = recording["sampling_rate_hz"]
    files = f" of {len(recording['parts'])} files" if recording.get("parts") else ""
    print(
        f"{counted(len(recording['segments']), 'still segment')} in {recording['n_samples']} samples{files} "
        f"{'without a sampling rate' if rate is None else f'at {rate:g} Hz'}; "
        f"used {body.get('segments_used', 'all')}"
    )


def _print_parts(body: dict, recording: dict) -> None:
    """One file per pose: what each file gave."""
    used = body.get("segments_used") or []
    for r, i in zip(body.get("readings") or [], used):
        up = recording["segments"][i]["up"]
        print(
            f"{r.get('source')}: {up + ' up' if up else f'no axis {WITHIN_LABEL_ANGLE}'}, mean "
            + "  ".join(f"{v:.4f}" for v in r["mean"])
        )


def print_model(model: dict, per_sensor: bool = False) -> None:
    """The model's parameters: a vector on one line, a matrix a row a line; of a model with a part per sensor
    (the cube's, :attr:`~app.calibration.shared.result.CalibrationResult.PER_SENSOR`), each sensor's S and b."""
    for name, value in model.items():
        if name == "type" or value is None:
            continue
        if per_sensor:
            print(f"{name}: S = {np.round(np.asarray(value['S']), 6).tolist()}, b = {np.round(value['b'], 6).tolist()}")
            continue
        arr = np.atleast_2d(np.asarray(value, dtype=float))
        print(f"{name} =" if arr.shape[0] > 1 else f"{name} = " + "  ".join(f"{v: .6f}" for v in arr[0]))
        if arr.shape[0] > 1:
            for row in arr:
                print("   " + "  ".join(f"{v: .6f}" for v in row))


def _print_figures(body: dict) -> None:
    """Why auto chose its method, the headline, and the fit's largest errors."""
    m = body["metrics"]
    if body.get("choice"):
        print(f"method auto chose {body['choice']['method']}: {body['choice']['why']}")
    if body.get("headline"):
        print(body["headline"])
    if "fit_error_max" in m:
        print(f"fit error max {m['fit_error_max']:.6f} (raw {m['fit_error_max_raw']:.6f})")
    if "norm_error_max" in m:
        print(f"norm error max {m['norm_error_max']:.6f} (raw {m['norm_error_max_raw']:.6f})")


def print_compasses(flight: dict) -> None:
    """A flight log's compasses side by side (app.workflows.flight_compasses): heading error before → after,
    orientation, the power's pull, agreement with the first compass, and one action each."""
    print("the log's compasses (heading error on segments left out, firmware's → trical's):")

    def deg(value) -> str:
        return "—" if value is None else f"{value:.1f}°"

    for row in flight["compasses"]:
        pull = row.get("pull")
        pulled = (
            f", {pull['per_unit']:.2f} {pull['unit']} ({pull['at_top_deg']:.0f}° at the top "
            f"{row['power_kind']}{'' if pull['determined'] else ', not determined'})"
            if pull
            else ""
        )
        agrees = {True: ", agrees with the first", False: ", inconsistent with the first", None: ""}[row["consistent"]]
        left = row.get("orientation_left_deg")
        mounted = row["orientation"] or "orientation not found"
        if left is not None and left > 5.0:
            mounted += f" ({left:.0f}° left: unresolved)"
        print(
            f"  compass {row['instance']}: {deg(row['before_deg'])} → {deg(row['after_deg'])}, "
            f"{mounted}{pulled}{agrees}: {row['action']}"
        )
    for check in flight.get("consistency") or []:
        first, other = check["pair"]
        print(
            f"  compass {other} against {first}: {check['xyz_angle_deg']:.0f}° apart, {check['xy_angle_deg']:.0f}° "
            f"horizontally, {check['xy_length_diff_ut']:.1f} µT horizontal difference "
            f"({'within' if check['consistent'] else 'beyond'} ArduPilot's 90°, 60°, 20 µT)"
        )


def print_verdict(body: dict) -> None:
    """The verdict first (app.verdict): whether to apply the calibration, and why."""
    v = body.get("verdict")
    if v:
        print(v["words"])
        if v["why"]:
            print(f"  {v['why']}")


class ProgressBar:
    """A one-line progress bar on stderr, drawn only on a terminal."""

    def __init__(self, label: str, stream=None):
        self.stream = stream or sys.stderr
        self.label = label
        self.last = -1

    def __call__(self, done: int, total: int) -> None:
        pct = int(100 * done / total) if total else 100
        if pct == self.last:
            return
        self.last = pct
        filled = pct * 30 // 100
        self.stream.write(
            f"\r{self.label} [{'#' * filled}{'.' * (30 - filled)}] {pct:3d}% "
            f"{done / 1e6:.1f}/{total / 1e6:.1f} M samples"
        )
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def print_autocal(body: dict, verbose: bool = False) -> None:
    body = render_body(body, "cli")
    det = body["detection"]
    print(
        f"{body['label']}: {det['n_rest']} rest segments of {det['n_segments']} ({det['segment_s']:g} s; "
        f"{det['n_moving']} moving, {det['n_nan']} NaN, {det['n_idle']} idle sleep); ok = {body['ok']}"
    )
    print_verdict(body)
    if body.get("headline"):
        print(body["headline"])
    print("points per subset C_ij: " + ", ".join(f"{k} {v}" for k, v in body["selection"].items()))
    model = body["model"]
    print("K =")
    for row in model["K"]:
        print("   " + "  ".join(f"{v: .6f}" for v in row))
    print("o = " + "  ".join(f"{v: .6f}" for v in model["o"]))
    if body["comparison"]:
        print(f"{'method':<22}{'before mg':>10}{'after mg':>10}{'R %':>9}  points")
        for name, row in body["comparison"].items():
            errors = NormErrors.of(row)
            if errors.after is None:
                print(f"{name:<22}{'-':>10}{'-':>10}{'-':>9}  {row.get('count')}")
                continue
            print(
                f"{name:<22}{errors.before:>10.2f}{errors.after:>10.2f}"
                f"{row['improvement_pct'] or 0:>9.0f}  {row.get('count')}"
            )
    print_notes(body["warnings"], verbose)


def print_folder_table(bodies: list[dict]) -> None:
    bodies = [render_body(b, "cli") for b in bodies]
    name_w = max(8, *(len(b.get("label") or "") for b in bodies))
    # "tilt": the worst tilt a level reads with the cv error (app.calibration.shared.angles).
    print(
        f"{'file':<{name_w}}  {'ok':<5}{'rest':>7}{'points':>7}{'cv mg':>8}{'tilt':>8}{'before mg':>10}{'after mg':>10}"
        f"{'R %':>8}  note"
    )
    for b in bodies:
        if "error" in b:
            print(
                f"{b['label']:<{name_w}}  {'error':<5}{'':>7}{'':>7}{'':>8}{'':>8}{'':>10}{'':>10}{'':>8}  "
                f"{render(b['error'], 'cli')}"
            )
            continue
        m, errors = b["metrics"], NormErrors.of(b["metrics"])
        cv = "-" if errors.on_new_orientations is None else f"{errors.on_new_orientations:.2f}"
        tilt = "-" if errors.on_new_orientations is None else degrees_text(tilt_error_deg(errors.on_new_orientations))
        before = "-" if errors.before is None else f"{errors.before:.2f}"
        after = "-" if errors.after is None else f"{errors.after:.2f}"
        r = "-" if not m.get("improvement_pct") else f"{m['improvement_pct']:.0f}"
        note = b["reasons"][0] if b["reasons"] else ""
        print(
            f"{b['label']:<{name_w}}  {b['ok']!s:<5}{b['detection']['n_rest']:>7}{m['count']:>7}{cv:>8}{tilt:>8}"
            f"{before:>10}{after:>10}{r:>8}  {note[:100]}"
        )
    n_ok = sum(1 for b in bodies if b.get("ok"))
    print(f"{n_ok} of {len(bodies)} recordings calibrated")


def print_temperature(body: dict, verbose: bool = False) -> None:
    body = render_body(body, "cli")
    stored = f", id {body['id']}" if body.get("id") else ""
    print(f"{body.get('label') or ''}: ok = {body['ok']}{stored}")
    print_verdict(body)
    for reason in body.get("reasons") or []:
        print(f"  reason: {reason}")
    for sensor, model in body["model"].items():
        if sensor == "type":
            continue
        m, unc = body["metrics"][sensor], body["uncertainty"][sensor]
        print(
            f"{sensor} ({model['unit']}), {model['t_min_c']:.1f}–{model['t_max_c']:.1f} °C, T_ref "
            f"{model['t_ref_c']:.2f} °C, offset = X0 + X1 dT + X2 dT^2 + X3 dT^3:"
        )
        for i, axis in enumerate("xyz"):
            cells = "  ".join(
                f"X{k} {c:.4g} ± {h:.2g}"
                for k, (c, h) in enumerate(zip(model["coefficients"][i], unc["coefficients"][i]))
            )
            print(
                f"  {axis}: order {model['order'][i]}  {cells}  drift {m['drift_raw'][i]:.3g} → {m['drift_cv'][i]:.3g} "
                f"{m['unit']} (bands left out)"
            )
        print(f"  samples per band: {', '.join(str(n) for n in m['samples_per_band'])}")
    print_notes(body.get("warnings"), verbose)


def print_noise(body: dict, verbose: bool = False) -> None:
    body = render_body(body, "cli")
    still = body.get("still") or {}
    print(
        f"{body.get('label') or ''}: {body['duration_s']:.1f} s still at {body['sampling_rate_hz']:g} Hz "
        f"({100 * still.get('fraction', 1):.0f} % of the recording); ok = {body['ok']}"
    )
    print_verdict(body)
    names = {
        "noise_density": "noise density N",
        "random_walk": "random walk K",
        "bias_instability": "bias instability B",
    }
    for sensor in ("gyr", "acc", "mag"):
        model = body["model"].get(sensor)
        if not model:
            continue
        unc = body["uncertainty"][sensor]
        print(f"{sensor} ({model['unit']}):")
        for term, label in names.items():
            unit = model[f"{term}_unit"]
            cells = []
            for v, iv in zip(model[term], unc[term]):
                cells.append("null" if v is None else f"{v:.4g} [{iv[0]:.3g}, {iv[1]:.3g}]")
            print(f"  {label:<20} {unit:<12} x {cells[0]}  y {cells[1]}  z {cells[2]}")
        print(f"  {'bias':<20} {model['unit']:<12} " + "  ".join(f"{a} {v:.6g}" for a, v in zip("xyz", model["bias"])))
    for r in body["reasons"]:
        print(f"reason: {r}")
    print_notes(body["warnings"], verbose)


def _interval(figure: dict | None) -> str:
    if figure is None:
        return "-"
    angle = "" if figure.get("value_deg") is None else f", {figure['value_deg']:.2f}°"
    return f"{figure['value']:.2f} {figure['unit']} (95 % {figure['low']:.2f}–{figure['high']:.2f}{angle})"


def print_check(out: dict) -> None:
    """A check's verdict, then each sensor's error now and a fresh calibration's, what drifted and the reasons."""
    from app.calibration.check import VERDICT_WORDS

    print(f"verdict: {VERDICT_WORDS[out['verdict']]}")
    for s in out["sensors"]:
        print(f"  {s['sensor']}: {VERDICT_WORDS[s['verdict']]} ({s['count']} readings)")
        if s["current"] is not None:
            print(f"    current calibration: {_interval(s['current'])}")
        if s["fresh"] is not None:
            print(f"    fresh calibration:   {_interval(s['fresh'])}")
        if s["drifted"]:
            print(f"    drifted: {', '.join(s['drifted'])}")
        for reason in s["reasons"]:
            print(f"    - {reason}")


def print_comparison(out: dict) -> None:
    """Two calibrations compared: per sensor, each parameter's difference B − A with its interval, the real ones
    marked, and the effect as a tilt or a heading."""
    print(f"{out['with'] or 'B'} − {out['calibration_id'] or 'A'}")
    for s in out["sensors"]:
        angle = "" if s["effect_deg"] is None else f", a {s['effect_kind']} off by up to {s['effect_deg']:.2f}°"
        print(f"  {s['sensor']}: at most {s['effect']:.3g} {s['effect_unit']}{angle}")
        for d in s["differences"]:
            hw = "no interval" if d["half_width"] is None else f"± {d['half_width']:.3g}"
            mark = "  real" if d["real"] else ""
            axis = f" {d['axis']}" if d["axis"] else ""
            print(f"    {d['parameter']}{axis}: {d['difference']:+.3g} {d['unit']} {hw}{mark}")
    if out["missing"]:
        print(f"  only one of them corrects: {', '.join(out['missing'])}")
