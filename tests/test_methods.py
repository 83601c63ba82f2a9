"""The method table (app/methods.py) is the one declaration of each method: the request and response unions,
the CLI's choices and commands and the export formats all come from its entries, and the workflow no
longer decides anything by comparing a method's name."""

from __future__ import annotations

import argparse
import contextlib
import io
import typing
from pathlib import Path

import pytest

from app import methods
from app.api.schemas import calibrations
from app.cli.calibrate import calibration_request
from app.cli.parser import build_parser
from app.io import log as io_log
from app.io.exports.compass import FLIGHT_COMPASS_EXPORTERS
from app.io.exports.exporters import EXPORTERS
from app.io.exports.noise import NOISE_EXPORTERS
from app.io.exports.temperature import TEMPERATURE_EXPORTERS

ROOT = Path(__file__).resolve().parent.parent


def literal_method(model) -> str:
    """The one value a model's ``method`` field admits."""
    (value,) = typing.get_args(model.model_fields["method"].annotation)
    return value


def union_members(annotated) -> tuple:
    union, _ = typing.get_args(annotated)
    return typing.get_args(union)


def subcommands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(sub.choices)


def option(parser: argparse.ArgumentParser, flag: str) -> argparse.Action:
    (action,) = [a for a in parser._actions if flag in a.option_strings]
    return action


def test_every_request_model_of_the_union_is_an_entry_of_its_own_name():
    members = union_members(methods.CalibrationIn)
    assert members == tuple(m.request for m in methods.TABLE)
    assert [literal_method(model) for model in members] == [m.name for m in methods.TABLE]
    assert methods.METHODS == (
        "auto",
        "six_position",
        "orientations",
        "nonorthogonal",
        "triangular",
        "cube",
        "autocal",
        "noise",
        "magnetometer",
        "temperature",
        "compass_flight",
        "imported",
    )


def test_every_response_model_of_the_union_is_an_entry_of_its_own_name():
    members = union_members(calibrations.CalibrationOut)
    named = [m for m in methods.TABLE if m.response != methods.AS_CHOSEN]
    assert [model.__name__ for model in members] == [m.response or f"CalibrationOut_{m.name}" for m in named]
    assert [literal_method(model) for model in members] == [m.name for m in named]
    assert {m.name: model for m, model in zip(named, members)} == calibrations.RESPONSE_MODELS
    # auto answers as the method it chose, each of which has its own entry and response.
    assert [m.name for m in methods.TABLE if m.response == methods.AS_CHOSEN] == ["auto"]
    # A method without a response model of its own answers with the fields every calibration has.
    plain = calibrations.common_response("plain")
    assert issubclass(plain, calibrations.CalibrationCommon) and literal_method(plain) == "plain"


def test_the_dispatch_is_the_entry_handler():
    for method in methods.TABLE:
        assert callable(method.handler) and method.handler.__module__.startswith("app.workflows."), method.name
    assert len({m.handler for m in methods.TABLE}) == len(methods.TABLE)  # no handler branches on the name


def test_the_cli_method_choices_and_commands_come_from_the_table():
    commands = subcommands()
    assert tuple(option(commands["calibrate"], "--method").choices) == methods.commanded_by("calibrate")
    assert methods.commanded_by("calibrate") == (
        "auto",
        "six_position",
        "orientations",
        "nonorthogonal",
        "triangular",
        "cube",
        "magnetometer",
        "compass_flight",
    )
    for method in methods.TABLE:
        assert method.command in commands, method.name
    # --solver names the methods whose request takes a solver, and offers the solvers of the core.
    solver = option(commands["calibrate"], "--solver")
    assert solver.help.startswith("triangular only:")
    assert tuple(solver.choices) == methods.BY_NAME["triangular"].solvers == methods.BY_NAME["autocal"].solvers
    assert [m.name for m in methods.TABLE if m.solvers] == ["triangular", "autocal"]


def test_the_export_formats_come_from_the_table():
    assert tuple(option(subcommands()["export"], "--format").choices) == methods.ALL_FORMATS
    assert set(methods.ALL_FORMATS) == (
        set(EXPORTERS) | set(NOISE_EXPORTERS) | set(TEMPERATURE_EXPORTERS) | set(FLIGHT_COMPASS_EXPORTERS)
    )
    assert methods.BY_NAME["compass_flight"].formats == tuple(FLIGHT_COMPASS_EXPORTERS)
    assert methods.BY_NAME["noise"].formats == tuple(NOISE_EXPORTERS)
    assert methods.BY_NAME["temperature"].formats == tuple(TEMPERATURE_EXPORTERS)
    for name in (
        "auto",
        "six_position",
        "orientations",
        "nonorthogonal",
        "triangular",
        "cube",
        "autocal",
        "magnetometer",
    ):
        assert methods.BY_NAME[name].formats == tuple(EXPORTERS)


def test_what_a_method_takes_is_read_from_its_request_model():
    assert [m.name for m in methods.TABLE if m.needs_recording] == [
        "cube",
        "autocal",
        "noise",
        "temperature",
        "compass_flight",
    ]
    compass = methods.BY_NAME["magnetometer"].options
    assert "field_ut" in compass and "gravity" not in compass
    assert "method" not in methods.BY_NAME["cube"].options and "sections" in methods.BY_NAME["cube"].options


def cli_request(argv: list[str]) -> dict:
    args = build_parser().parse_args(["calibrate", *argv])
    return calibration_request(args, unit="g", method=args.method or "auto")


def test_the_cli_builds_each_method_request_from_the_options_its_model_takes():
    common = {"recording_id": "log.csv", "label": "log.csv"}
    assert cli_request(["log.csv", "--method", "triangular", "--solver", "fixed16", "--field-ut", "50"]) == {
        "method": "triangular",
        **common,
        "unit": "g",
        "solver": "fixed16",
    }
    assert cli_request(["log.csv", "--method", "nonorthogonal", "--solver", "fixed16", "--gravity", "9.81"]) == {
        "method": "nonorthogonal",
        **common,
        "unit": "g",
        "gravity": 9.81,
    }
    assert cli_request(
        [
            "log.csv",
            "--method",
            "magnetometer",
            "--gravity",
            "9.81",
            "--field-ut",
            "48.5",
            "--latitude-deg",
            "60.2",
            "--longitude-deg",
            "24.9",
            "--device-id",
            "b1",
        ]
    ) == {
        "method": "magnetometer",
        **common,
        "latitude_deg": 60.2,
        "longitude_deg": 24.9,
        "field_ut": 48.5,
        "device_id": "b1",
    }
    assert cli_request(["log.csv", "--method", "cube", "--field-ut", "50", "--protocol", "ferraris"]) == {
        "method": "cube",
        **common,
        "protocol": "ferraris",
        "field_ut": 50.0,
    }
    for argv in (["log.csv"], ["log.csv", "--method", "six_position", "--protocol", "ferraris"]):
        request = cli_request(argv)
        methods.parse_calibration_request(request)  # every request the CLI builds is a valid one
        assert set(request) == {"method", "recording_id", "label", "unit"}


def test_a_method_with_no_entry_is_refused_naming_the_methods():
    from pydantic import ValidationError

    from app.methods import describe_errors

    with pytest.raises(ValidationError) as caught:
        methods.parse_calibration_request({"method": "auto_compass", "recording_id": "rec_1"})
    words = describe_errors(caught.value.errors())
    assert "auto_compass" in words and all(f"'{name}'" in words for name in methods.METHODS), words
    err = io.StringIO()
    with contextlib.redirect_stderr(err), pytest.raises(SystemExit) as exit_:
        build_parser().parse_args(["calibrate", "log.csv", "--method", "noise"])
    assert exit_.value.code == 2
    assert "invalid choice: 'noise'" in err.getvalue() and "'magnetometer'" in err.getvalue()


def test_the_unit_tables_are_io_s():
    assert set(io_log.TO_SI) == set(io_log.UNITS) == set(io_log.SI_UNITS)
    for sensor, units in io_log.UNITS.items():
        assert set(io_log.TO_SI[sensor]) == set(units)
        assert io_log.TO_SI[sensor][io_log.SI_UNITS[sensor]] == 1.0
