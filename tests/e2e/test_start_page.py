"""The start page in real Chromium at a phone's viewport: paste six readings, upload a log."""

from __future__ import annotations

import json
import re

import numpy as np

from app.calibration import fit_six_position
from app.reach.tls import lan_addresses
from tests.conftest import DATA, seed_table
from tests.e2e.conftest import shot


def read_matrix(page, selector):
    return np.array(
        [
            [float(td) for td in row]
            for row in page.eval_on_selector_all(
                f"{selector} tr", "rows => rows.map(r => [...r.cells].map(c => c.textContent))"
            )
        ]
    )


def test_paste_six_readings(page, server):
    t1 = seed_table(1)
    page.goto(server.url + "/")
    shot(page, "start_page")
    page.fill("#paste", "\n".join(" ".join(repr(float(v)) for v in row) for row in t1[:6]))
    page.click("#fill")
    assert page.input_value('input[name="+zz"]') == repr(float(t1[5][2]))
    page.fill("#r-gravity", "9.81")
    page.click("#readings-form button[type=submit]")
    page.wait_for_selector("#result:not([hidden])")
    shot(page, "start_page_result")
    expected = fit_six_position(t1[:6], gravity=9.81)
    np.testing.assert_allclose(read_matrix(page, "#result-X"), expected.X, atol=1e-6)
    np.testing.assert_allclose(read_matrix(page, "#result-y").ravel(), expected.y, atol=1e-6)
    assert "passed its checks" in page.text_content("#result-ok")
    # The verdict first, then the one file for the use chosen (a phone app by default), then every format.
    page.wait_for_selector("#downloads[data-ready=true]")
    words = page.text_content("#verdict-words")
    assert (
        words.startswith("Apply it: error on the 6 poses fitted ")
        and page.get_attribute("#verdict", "data-kind") == "apply"
    )
    assert page.get_attribute("#use-file", "data-format") == "json" and "M · (reading − o)" in page.text_content(
        "#use-how"
    )
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => [a.textContent, a.href])")
    assert [name for name, _ in links] == ["JSON", "C header", "ArduPilot", "PX4", "Betaflight", "INAV", "YAML", "CSV"]
    for name, href in links:  # every link is a real export of this calibration, fetched by the page
        assert href.startswith("blob:"), name
        with page.expect_download() as info:
            page.click(f"#downloads a:text-is('{name}')")
        assert info.value.suggested_filename.startswith(("cal_", "trical_cal_")), name
    page.select_option("#use-with", "ardupilot")
    assert page.get_attribute("#use-file", "data-format") == "ardupilot"
    assert "Mission Planner" in page.text_content("#use-how")
    # remembered for calibrations of this source (a plain CSV: none), over the source's default (app/web/uses.py)
    assert page.evaluate("() => localStorage.getItem('trical.use.calibration.any')") == "ardupilot"
    shot(page, "start_page_result_ardupilot")
    assert page.errors == []


def upload_six_orientations(page, server):
    """Open the start page and upload the six-orientation log at 150 Hz (its rate under Options)."""
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(DATA / "six_orientations_150hz.csv"))
    page.click("#options-summary")
    page.fill("#log-rate", "150")
    page.click("#upload-form button[type=submit]")


def test_upload_a_log(page, server):
    upload_six_orientations(page, server)
    page.wait_for_selector("#segments:not([hidden])")
    ups = page.eval_on_selector_all("#segments-table tbody tr", "rows => rows.map(r => r.cells[2].textContent)")
    assert {"-x", "+x", "-y", "+y", "-z", "+z"} <= set(ups)
    # Times in seconds, not sample indices; the plot shades each still segment.
    first = page.eval_on_selector_all("#segments-table tbody tr:first-child td", "cs => cs.map(c => c.textContent)")
    assert first[0] == "1" and re.fullmatch(r"\d+\.\d–\d+\.\d", first[1]), first
    assert page.locator("#log-plot svg rect.still").count() == len(ups)
    # method auto at once: no second click; the verdict first.
    page.wait_for_selector("#result:not([hidden])")
    page.wait_for_selector("#downloads[data-ready=true]")
    shot(page, "upload_result")
    assert page.text_content("#verdict-words").startswith("Apply it: error on the 6 poses fitted ")
    assert "passed its checks" in page.text_content("#result-ok")
    # method auto: six axis poses → six_position, said in words; the headline says that six poses give
    # no figure for new orientations, and how to get one.
    choice = page.text_content("#result-choice")  # the method named once, then why
    assert choice.startswith("Method: six positions (accelerometer), chosen because the 6 poses are the six axis")
    assert choice.count("six positions (accelerometer)") == 1, choice
    headline = page.text_content("#result-headline")
    assert headline.startswith("no figure for new orientations") and "add poses" in headline
    assert "on the poses fitted (in-sample)" in headline
    assert page.errors == []


def test_an_unrecognised_header_is_mapped_by_hand_and_stale_output_is_cleared(page, server, tmp_path):
    upload_six_orientations(page, server)
    page.wait_for_selector("#downloads[data-ready=true]")
    # The same log with a header trical does not know: a control per column, and nothing stale on show.
    renamed = tmp_path / "north_east_down.csv"
    lines = (DATA / "six_orientations_150hz.csv").read_text().splitlines()
    # Five columns (pressure and humidity beside the accelerometer): a layout the data cannot name either.
    renamed.write_text(
        "\n".join(["north,east,down,pressure,humidity"] + [ln + ",1013.2,45" for ln in lines[1:]]) + "\n"
    )
    page.set_input_files("#log-file", str(renamed))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#columns-map:not([hidden])")
    assert page.locator("#result").is_hidden() and page.locator("#segments").is_hidden()
    assert page.text_content("#upload-msg") == "Say which column is which, below."
    shot(page, "upload_column_map")
    columns = page.eval_on_selector_all("#columns-map-list select", "ss => ss.map(s => s.dataset.column)")
    assert columns == ["north", "east", "down", "pressure", "humidity"]
    for name, role in zip(columns, ("acc_x", "acc_y", "acc_z")):
        page.select_option(f"#columns-map-list select[data-column={name}]", role)
    page.click("#columns-map-go")
    page.wait_for_selector("#downloads[data-ready=true]")
    assert page.locator("#columns-map").is_hidden()
    assert page.text_content("#verdict-words").startswith("Apply it: ")
    assert len(page.errors) == 1 and "422" in page.errors[0]  # the browser logs the refused upload


def test_upload_a_headerless_log_with_its_columns(page, server):
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(DATA / "formats" / "headerless_imu_comma.csv"))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#segments:not([hidden])")  # time, accelerometer, gyroscope: read from the data
    assert page.locator("#columns-map").is_hidden()
    refused = list(page.errors)
    page.click("#options-summary")
    page.fill("#log-columns", "t,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z")
    page.select_option("#log-sign", "-1")
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#segments:not([hidden])")
    ups = page.eval_on_selector_all("#segments-table tbody tr", "rows => rows.map(r => r.cells[2].textContent)")
    truth = json.loads((DATA / "formats" / "format_samples.json").read_text())["labels"]
    assert ups == [{"+": "-", "-": "+"}[u[0]] + u[1] for u in truth]  # negated: every rest upside down
    assert page.errors == refused


def test_a_bad_line_is_named_before_any_question_of_columns(page, server):
    page.goto(server.url + "/")
    page.set_input_files(
        "#log-file",
        {"name": "bad_line.csv", "mimeType": "text/csv", "buffer": b"acc_x,acc_y,acc_z\n0.1,0.2,9.8\n0.1,abc,9.8\n"},
    )
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#upload-msg:has-text('Upload refused')")
    assert "line 3, column 'acc_y': 'abc' is not a number" in page.text_content("#upload-msg")
    assert page.locator("#columns-map").is_hidden()


def test_columns_the_data_leave_open_are_chosen_on_the_card(page, server):
    # A real still MPU-6050 gyroscope in counts, no header row: a gyroscope's offset or a compass's field.
    still = DATA / "real" / "corpus" / "mpu6050_still_gyro_counts_headerless" / "imu_static_test_cols456.csv"
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(still))
    page.click("#options-summary")
    page.fill("#log-rate", "100")
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#columns-map:not([hidden])")
    assert page.text_content("#upload-msg") == "Say which column is which, below."
    assert page.text_content("#columns-map-hint").startswith("The columns of this file can be read more than one way")
    assert page.text_content(".columns-preview").startswith("-480,193,-83")
    assert page.locator(".columns-plots svg").count() == 3
    # Each plot on its own scale, with its range and what the reading chosen makes of it (whole numbers: counts).
    captions = page.eval_on_selector_all(".columns-plots figcaption", "cs => cs.map(c => c.textContent)")
    assert captions[0] == "column 1, gyroscope x: -480 to -386 (counts)", captions
    page.check("#columns-map-list input[value='mag_x,mag_y,mag_z']")
    assert page.text_content(".columns-plots figcaption").startswith("column 1, magnetometer x: "), captions
    choices = page.eval_on_selector_all("#columns-map-list input[name=columns-candidate]", "rs => rs.map(r => r.value)")
    assert choices == ["gyr_x,gyr_y,gyr_z", "mag_x,mag_y,mag_z"]
    shot(page, "upload_columns_candidates")
    page.check("#columns-map-list input[value='gyr_x,gyr_y,gyr_z']")
    page.click("#columns-map-go")
    page.wait_for_selector("#segments:not([hidden])")
    assert page.locator("#columns-map").is_hidden()
    assert "gyroscope" in page.text_content("#supports-holds")


def test_several_files_are_each_asked_their_columns_on_the_card(page, server, tmp_path):
    """Two files of a still MPU-6050's gyroscope in counts without a header row, chosen together: the card asks
    about each in turn (a question, not a refusal in red), and the recording reads each with its own answer."""
    from tests.api.test_columns_per_file import _two_files

    paths = []
    for _, (name, content, _mime) in _two_files():
        (tmp_path / name).write_bytes(content)
        paths.append(str(tmp_path / name))
    page.goto(server.url + "/")
    page.set_input_files("#log-file", paths)
    page.click("#options-summary")
    page.fill("#log-rate", "100")
    page.click("#upload-form button[type=submit]")
    for name in ("rest_1.csv", "rest_2.csv"):
        page.wait_for_selector(f"#columns-map-list[data-file='{name}']")
        assert page.text_content("#upload-msg") == f"Say which column is which in {name}, below."
        assert page.locator("#upload-msg.bad").count() == 0  # a question, not a refusal
        assert page.text_content("#columns-map-hint").startswith(f"The columns of {name} (one of the files)")
        labels = page.eval_on_selector_all("#columns-map-list .columns-choice", "ls => ls.map(l => l.textContent)")
        assert labels[0].strip().startswith("gyroscope — 1: gyroscope x, 2: gyroscope y, 3: gyroscope z"), labels
        if name == "rest_1.csv":
            for width in (320, 390, 1280):
                page.set_viewport_size({"width": width, "height": 900})
                assert page.evaluate("() => document.documentElement.scrollWidth") <= width  # no sideways scroll
                shot(page, f"upload_columns_per_file_{width}")
        page.check("#columns-map-list input[value='gyr_x,gyr_y,gyr_z']")
        page.click("#columns-map-go")
    page.wait_for_selector("#segments:not([hidden])")
    assert "the gyroscope" in page.text_content("#supports-holds") and "of 2 files" in page.text_content(
        "#supports-holds"
    )
    assert page.errors == [] or all("422" in e for e in page.errors)


POSE_FILES = DATA / "real" / "mpu6050_pose_files"
POSE_ORDER = ("x_axis_pos", "x_axis_neg", "y_axis_pos", "y_axis_neg", "z_axis_pos", "z_axis_neg")


def upload_pose_files(page, server, paths):
    """A maker's six pose files (an MPU-6050's, in m/s² under an "aX (g)" header): chosen at once; the
    data decide the unit (m/s²), and a warning says what the header said."""
    page.goto(server.url + "/")
    page.set_input_files("#log-file", [str(p) for p in paths])
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#segments:not([hidden])")


def test_one_file_per_pose_chosen_at_once_is_one_calibration(page, server):
    upload_pose_files(page, server, [POSE_FILES / f"{s}.csv" for s in POSE_ORDER])
    rows = page.eval_on_selector_all(
        "#segments-table tbody tr", "rows => rows.map(r => [...r.cells].map(c => c.textContent))"
    )
    assert [(r[2], r[4]) for r in rows] == [
        ("+x", "x_axis_pos.csv"),
        ("-x", "x_axis_neg.csv"),
        ("+y", "y_axis_pos.csv"),
        ("-y", "y_axis_neg.csv"),
        ("+z", "z_axis_pos.csv"),
        ("-z", "z_axis_neg.csv"),
    ]
    assert page.locator("#segments-table th.file-col").is_visible()
    page.wait_for_selector("#result:not([hidden])")
    page.wait_for_selector("#downloads[data-ready=true]")
    shot(page, "start_page_pose_files")
    assert page.get_attribute("#verdict", "data-kind") == "apply"
    choice = page.text_content("#result-choice")  # the method named once, then why
    assert choice.startswith("Method: six positions (accelerometer), chosen because the 6 poses are the six axis")
    assert choice.count("six positions (accelerometer)") == 1, choice
    readings = page.eval_on_selector_all(
        "#result-readings tbody tr", "rows => rows.map(r => [r.cells[0].textContent, r.cells[3].textContent])"
    )
    assert sorted(map(tuple, readings)) == sorted(
        [
            ("+x", "x_axis_pos.csv"),
            ("-x", "x_axis_neg.csv"),
            ("+y", "y_axis_pos.csv"),
            ("-y", "y_axis_neg.csv"),
            ("+z", "z_axis_pos.csv"),
            ("-z", "z_axis_neg.csv"),
        ]
    )
    # Nothing to say of the files but how their time column was read.
    assert page.text_content("#segments-notes") == "time column 'Timestamp' read in ms (from its step)"
    assert page.errors == []


def test_a_zip_of_pose_files_with_a_misnamed_one_is_labelled_by_the_data(page, server, tmp_path):
    import zipfile

    names = {s: f"{s}.csv" for s in POSE_ORDER}
    names.update(z_axis_pos="z_axis_neg.csv", z_axis_neg="z_axis_pos.csv")  # two names swapped by hand
    path = tmp_path / "poses.zip"
    with zipfile.ZipFile(path, "w") as zf:
        for s in POSE_ORDER:
            zf.write(POSE_FILES / f"{s}.csv", f"poses/{names[s]}")
    upload_pose_files(page, server, [path])
    rows = page.eval_on_selector_all(
        "#segments-table tbody tr", "rows => rows.map(r => [r.cells[2].textContent, r.cells[4].textContent])"
    )
    assert rows[4:] == [["+z", "z_axis_neg.csv"], ["-z", "z_axis_pos.csv"]]
    notes = page.text_content("#segments-notes")
    assert "z_axis_neg.csv: its name says -z up, but its still readings point +z up" in notes
    assert "z_axis_pos.csv: its name says +z up, but its still readings point -z up" in notes
    page.wait_for_selector("#result:not([hidden])")
    warnings = page.eval_on_selector_all("#result-warnings li", "lis => lis.map(l => l.textContent)")
    assert any(w.startswith("z_axis_neg.csv names -z up, but its still reading points +z up") for w in warnings)
    assert page.get_attribute("#verdict", "data-kind") == "apply"
    assert page.errors == []


def test_bad_paste_is_explained(page, server):
    page.goto(server.url + "/")
    page.fill("#paste", "1 2 3\n4 5")
    page.click("#fill")
    assert "expected 6 lines" in page.text_content("#fill-msg") and page.locator("#fill-msg").is_visible()


def test_noise_of_an_uploaded_still_recording(page, server, tmp_path):
    # Ten minutes of a still board at 100 Hz with known white noise, flicker and random walk
    # (simulations.noise): the page shows each term per axis with its unit, and the
    # Allan plot the server draws.
    from simulations.noise import simulate_still

    rng = np.random.default_rng(5)
    n, fs = 60_000, 100.0
    gyr = simulate_still(rng, n_samples=n, sampling_rate_hz=fs, N=1e-3, B=1e-4, K=3e-4)
    acc = simulate_still(rng, n_samples=n, sampling_rate_hz=fs, N=2e-3, B=3e-4, K=1e-3, bias=[0.1, -0.2, 9.81])
    path = tmp_path / "still.csv"
    np.savetxt(
        path,
        np.column_stack([np.arange(n) / fs, acc, gyr]),
        delimiter=",",
        comments="",
        fmt="%.9g",
        header="time_s,acc_x,acc_y,acc_z,gyr_x,gyr_y,gyr_z",
    )
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(path))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#segments:not([hidden])")
    # The recording says what it can do: one still pose is no accelerometer calibration (said as a fact, not in
    # red), one long rest is the noise, which runs at once.
    items = page.locator("#supports-list li")
    assert items.nth(0).get_attribute("data-method") == "auto" and items.nth(0).get_attribute("data-ready") == "false"
    assert "1 still pose" in items.nth(0).text_content()
    assert items.nth(1).get_attribute("data-method") == "noise" and items.nth(1).get_attribute("data-ready") == "true"
    page.wait_for_selector("#result:not([hidden])")
    assert page.locator("#segments-msg.bad").count() == 0
    page.wait_for_function("() => document.querySelector('#result-allan img').naturalWidth > 0")
    for width in (320, 390, 1280):
        page.set_viewport_size({"width": width, "height": 900})
        shot(page, f"start_page_noise_{width}")
    row = page.locator('#result-noise-gyr tr[data-term="noise_density"] td')
    assert row.last.text_content() == "rad/s/√Hz"
    density = [float(row.nth(i).text_content()) for i in range(3)]
    assert all(0.8e-3 < d < 1.25e-3 for d in density), density  # N = 1e-3 rad/s/√Hz, within its interval
    assert page.locator("#result-readings").is_hidden()
    page.wait_for_selector("#downloads[data-ready=true]")
    assert page.get_attribute("#verdict", "data-kind") == "figures"
    assert page.text_content("#verdict-words").startswith("Use these figures in your filter")
    assert page.get_attribute("#use-file", "data-format") == "kalibr" and "--imu imu.yaml" in page.text_content(
        "#use-how"
    )
    links = page.eval_on_selector_all("#downloads a", "as => as.map(a => [a.textContent, a.href])")
    assert [name for name, _ in links] == [
        "Kalibr imu.yaml",
        "OpenVINS",
        "VINS-Fusion",
        "JSON",
        "CSV (Allan table)",
        "Allan plot (SVG)",
    ]
    for name, _href in links:  # every link is a real export of this characterisation, fetched by the page
        with page.expect_download() as info:
            page.click(f"#downloads a:text-is('{name}')")
        assert info.value.suggested_filename, name
    assert page.errors == []  # nothing was refused: no calibration nobody asked for was tried


def test_the_start_page_by_capability(browser, server):
    # A desktop (no touch screen): the phone page's QR code and address, the upload, no Start.
    desktop = browser.new_context(viewport={"width": 1280, "height": 800})
    page = desktop.new_page()
    page.goto(server.url + "/")
    assert page.evaluate("() => document.documentElement.dataset.device") == "desktop"
    assert page.locator("#on-phone").is_visible() and page.locator("#phone-start").is_hidden()
    # The phone's door (app.reach.phone_door): HTTPS at the LAN address, with a code for one phone.
    url = page.text_content("#phone-url")
    door_port = server.env["TRICAL_PHONE_PORT"]
    assert re.fullmatch(rf"https://{re.escape(lan_addresses()[0])}:{door_port}/phone\?pass=[2-9a-z]{{10}}", url), url
    assert page.get_attribute("#phone-qr", "alt") == f"QR code of {url}"
    assert "lets in one phone, for 10 minutes" in page.text_content("#phone-door")
    assert page.locator("#upload-form").is_visible()
    assert "serve --https" not in page.text_content("main")  # operator hints are in the README
    shot(page, "start_page_desktop_1280")
    desktop.close()
    # A phone (touch screen, motion events): Start first, no QR code of itself.
    phone = browser.new_context(viewport={"width": 390, "height": 844}, is_mobile=True, has_touch=True)
    page = phone.new_page()
    page.goto(server.url + "/")
    assert page.evaluate("() => document.documentElement.dataset.device") == "phone"
    assert page.locator("#phone-start .cta").first.is_visible() and page.locator("#on-phone").is_hidden()
    assert page.get_attribute("#phone-start .cta >> nth=0", "href") == "/wizard?protocol=six"
    shot(page, "start_page_phone_390")
    phone.close()


def test_the_units_each_sensor_shows_and_a_part_for_counts(page, server, tmp_path):
    # A six-pose log whose header says g over m/s², beside a magnetometer in the AK8963's raw counts
    # (0.15 µT per count at 16 bits), as a maker's sketch prints them.
    from simulations.logs import simulate_static_log
    from simulations.magnetometer import simulate_session

    six = simulate_static_log(np.random.default_rng(22), sampling_rate_hz=50.0, rest_s=(3.0, 3.5), turn_s=(1.0, 1.2))
    n = len(six.samples)
    mag, _, _ = simulate_session(7, n=n)
    path = tmp_path / "board.csv"
    rows = [
        f"{i / 50:.2f}," + ",".join(f"{v:.5f}" for v in a) + "," + ",".join(f"{round(v / 0.15)}" for v in m)
        for i, (a, m) in enumerate(zip(six.samples, mag))
    ]
    path.write_text("\n".join(["t,aX (g),aY (g),aZ (g),mx,my,mz"] + rows) + "\n")
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(path))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#units:not([hidden])")
    # One menu per sensor the file has, set to what the data show; the reader's warnings above them.
    menus = page.eval_on_selector_all("#units-list select[id^=unit-]", "ss => ss.map(s => [s.id, s.value])")
    assert menus == [["unit-acc", "m/s^2"], ["unit-mag", "raw"]]
    warnings = page.eval_on_selector_all("#units-warnings li", "ls => ls.map(l => l.textContent)")
    assert warnings[0].startswith("the header said g for the accelerometer") and "calibrated in m/s^2" in warnings[0]
    assert any("the magnetometer's readings are counts" in w for w in warnings)
    mag_units = page.eval_on_selector_all("#unit-mag option", "os => os.map(o => o.textContent)")
    assert mag_units == ["µT", "nT", "gauss", "counts"]
    page.wait_for_selector("#downloads[data-ready=true]")
    page.click("#compass-recording")  # the compass in counts: its figures say counts, never µT
    page.wait_for_function("() => /counts/.test(document.querySelector('#verdict-words').textContent)")
    assert "µT" not in page.text_content("#verdict-words")
    page.wait_for_selector("#downloads[data-ready=true]")
    refused = page.eval_on_selector_all("#downloads li span", "ss => ss.map(s => s.textContent)")
    # firmware needs µT: they name the chip (Betaflight's and INAV's files, which take no compass, are not offered)
    assert [r.split(":")[0] for r in refused] == ["ArduPilot", "PX4"]
    assert all("upload the log again with the sensor's part menu" in r and "chip" not in r for r in refused)
    assert len(page.errors) == 2 and all("422" in e for e in page.errors)  # the browser logs the two refusals
    page.errors.clear()
    shot(page, "upload_units_counts")
    # The magnetometer's part: its counts become µT once the file is read again.
    page.select_option("#chip-mag", "ak8963-16bit")
    assert page.input_value("#unit-mag") == "raw"
    page.click("#units-go")
    page.wait_for_function(
        "() => document.querySelector('#unit-mag') && document.querySelector('#unit-mag').value === 'uT'"
    )
    assert page.input_value("#chip-mag") == "ak8963-16bit" and page.input_value("#unit-acc") == "m/s^2"
    warnings = page.eval_on_selector_all("#units-warnings li", "ls => ls.map(l => l.textContent)")
    assert not any("magnetometer" in w for w in warnings)
    page.wait_for_selector("#downloads[data-ready=true]")
    page.click("#compass-recording")
    page.wait_for_function("() => /µT/.test(document.querySelector('#verdict-words').textContent)")
    assert "counts" not in page.text_content("#verdict-words")
    assert page.errors == []


def test_an_upload_refused_for_its_unit_names_the_page_s_menus_and_shows_them(page, server, tmp_path):
    # An accelerometer whose header says g but whose rest fits no unit (0.3 g in m/s²): the refusal asks for
    # the unit. The API names acc_unit, lsb_per_g and chip; the page names its own menus, and shows them.
    from simulations.logs import simulate_static_log

    six = simulate_static_log(np.random.default_rng(22), sampling_rate_hz=50.0, rest_s=(3.0, 3.5), turn_s=(1.0, 1.2))
    path = tmp_path / "board.csv"
    rows = [f"{i / 50:.2f}," + ",".join(f"{0.3 * v:.5f}" for v in a) for i, a in enumerate(six.samples)]
    path.write_text("\n".join(["t,ax (g),ay (g),az (g)"] + rows) + "\n")
    page.goto(server.url + "/")
    page.set_input_files("#log-file", str(path))
    page.click("#upload-form button[type=submit]")
    page.wait_for_selector("#upload-msg.bad")
    said = page.text_content("#upload-msg")
    assert (
        said.startswith("Upload refused: ")
        and "the accelerometer's unit menu (in “Units, as the data show them”)" in said
    )
    assert "part menu" in said and not re.search(r"acc_unit|lsb_per_g|\bchip\b|--\w", said), said
    page.wait_for_selector("#units:not([hidden])")
    menus = page.eval_on_selector_all("#units-list select[id^=unit-]", "ss => ss.map(s => [s.id, s.value])")
    assert menus == [["unit-acc", ""], ["unit-gyr", ""], ["unit-mag", ""]]  # "as the data show": nothing sent
    shot(page, "upload_refused_for_its_unit")
    page.select_option("#unit-acc", "g")
    page.click("#units-go")  # read again with the unit chosen: still no unit fits, and the page still says why
    page.wait_for_function(
        "() => /Upload refused: .*unit menu .*said g\\)/.test(document.querySelector('#upload-msg').textContent)"
    )
    assert page.locator("#units").is_visible()
    page.errors.clear()  # the browser logs each 422


def test_a_computer_sees_a_board_and_the_upload_first_and_the_phone_s_needs_beside_them(browser, server):
    desktop = browser.new_context(viewport={"width": 1280, "height": 900})
    page = desktop.new_page()
    errors: list[str] = []
    page.on("console", lambda msg: errors.append(msg.text) if msg.type == "error" else None)
    page.goto(server.url + "/")
    assert page.locator("h1 .for-desktop").is_visible() and page.locator("h1 .for-phone").is_hidden()
    assert page.inner_text("h1") == "Calibrate the motion sensors of a phone, a board or a drone"  # what is shown
    # Three doors, each a heading a person scans, each to its own first step (issue 45).
    doors = page.locator("#doors .door")
    assert [doors.nth(i).locator(".door-h").inner_text() for i in range(3)] == [
        "A phone",
        "A board",
        "A drone's flight log",
    ]
    assert [doors.nth(i).get_attribute("href") for i in range(3)] == ["#on-phone", "#on-board", "#on-drone"]
    with page.expect_file_chooser() as chooser:  # the drone's first step: its log, in the upload's chooser
        page.click("#drone-log")
    assert chooser.value.is_multiple() and chooser.value.element.get_attribute("id") == "log-file"
    # Chromium has the Web Serial API: the board's flows lead, the upload under them, the QR code beside.
    board = page.locator("#on-board").bounding_box()
    upload = page.locator("#upload-form").bounding_box()
    phone = page.locator("#on-phone").bounding_box()
    assert board["y"] < upload["y"] and phone["x"] > board["x"] + board["width"] - 1 and phone["y"] < upload["y"]
    assert page.get_attribute("#board-flows .cta", "href") == "/wizard?protocol=six&source=board"
    assert page.locator("#board-no-serial").is_hidden()
    # The phone's address is the door's, over HTTPS: the page tells what the phone's browser will say of it.
    assert page.text_content("#phone-url").startswith("https://")
    assert "signed its own certificate" in page.text_content("#phone-door")
    # The upload's options show once a file is chosen, each only when it applies to it.
    assert page.locator("#options").is_hidden()
    page.set_input_files(
        "#log-file", [str(DATA / "real" / "mpu6050_pose_files" / f) for f in ("x_axis_pos.csv", "z_axis_neg.csv")]
    )
    page.wait_for_timeout(300)
    assert page.locator("#options").is_hidden()  # a time column, a header, no Core Motion names: nothing to choose
    page.set_input_files("#log-file", str(DATA / "six_orientations_150hz.csv"))
    page.click("#options-summary")
    assert page.text_content("#options-summary") == "Options: sampling rate"
    assert (
        page.locator("#log-rate").is_visible()
        and page.locator("#log-columns").is_hidden()
        and page.locator("#log-sign").is_hidden()
    )
    page.set_input_files("#log-file", str(DATA / "formats" / "headerless_imu_comma.csv"))
    expect_text = "Options: sampling rate, column names, sign"
    page.wait_for_function("(t) => document.querySelector('#options-summary').textContent === t", arg=expect_text)
    shot(page, "start_page_desktop_board_1280")
    desktop.close()
    # A browser without Web Serial (Safari, Firefox): which browsers have it, and the upload and `trical capture`.
    other = browser.new_context(viewport={"width": 1280, "height": 900})
    page = other.new_page()
    page.add_init_script("delete Navigator.prototype.serial; delete Navigator.prototype.bluetooth;")
    page.goto(server.url + "/")
    assert page.locator("#board-flows").is_hidden()
    words = page.text_content("#board-no-serial")
    assert "Chrome, Edge and Opera" in words and "not in Safari or Firefox" in words and "trical capture PORT" in words
    shot(page, "start_page_desktop_no_serial_1280")
    other.close()
    assert errors == []


def test_one_file_per_sensor_chosen_together_is_one_recording(page, server):
    """An iPhone's accelerometer.csv, gyroscope.csv and magnetometer.csv (tests/data/real/corpus), each with its
    own epoch time column: chosen together, they are one recording on the accelerometer's clock."""
    folder = DATA / "real" / "corpus" / "iphone_heading_per_sensor_files"
    upload_pose_files(page, server, [folder / f for f in ("accelerometer.csv", "gyroscope.csv", "magnetometer.csv")])
    notes = page.text_content("#segments-notes")
    assert (
        "one recording in 3 files, one per sensor: accelerometer.csv the accelerometer (g), gyroscope.csv the "
        "gyroscope (rad/s), magnetometer.csv the magnetometer (raw)" in notes
    )
    assert "merged on the clock of accelerometer.csv" in notes
    assert page.locator("#segments-table th.file-col").is_hidden()  # one recording, not files of poses


def test_json_files_are_offered_read_and_the_betaflight_export_is_refused_in_its_own_words(page, server, tmp_path):
    page.goto(server.url + "/")
    samples = tmp_path / "samples.json"
    samples.write_text(json.dumps([{"t": round(i * 0.01, 2), "x": 0.01, "y": -0.02, "z": 0.98} for i in range(300)]))
    page.set_input_files("#log-file", str(samples))
    page.wait_for_timeout(300)
    assert page.locator("#options").is_hidden()  # a key names the time: nothing to ask
    untimed = tmp_path / "untimed.json"
    untimed.write_text(json.dumps([[0.01, -0.02, 0.98]] * 300))
    page.set_input_files("#log-file", str(untimed))
    page.wait_for_function("() => document.querySelector('#options-summary').textContent === 'Options: sampling rate'")
    export = (
        DATA / "real" / "corpus" / "betaflight_mag_characterization_model" / "characterization_model_2026-06-26.json"
    )
    page.set_input_files("#log-file", str(export))
    page.click("#upload-form button[type=submit]")
    page.wait_for_function("() => document.querySelector('#upload-msg').textContent.startsWith('Upload refused')")
    assert "the Betaflight configurator's magnetometer characterization model" in page.text_content("#upload-msg")
    assert page.locator("#columns-map").is_hidden()
