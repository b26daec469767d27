"""Measurement files: round trips, the layout users have, every error message (file and line),
and a filter run from a file ≡ the scenario runner on the same measurements."""

import re

import numpy as np
import pytest
from numpy.testing import assert_array_equal

from rankedassign.tracking import (
    Exact,
    LMBFilter,
    MultiSensorLMBFilter,
    ShortChainGibbs,
    make_model,
    make_multisensor_model,
    make_multisensor_scenario,
    make_scenario,
    read_measurements,
    run_filter,
    run_multisensor_scenario,
    run_scenario,
    write_measurements,
)


def write(tmp_path, text, name="meas.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def assert_same_scans(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        if isinstance(x, tuple):
            assert isinstance(y, tuple) and len(x) == len(y)
            for u, v in zip(x, y, strict=True):
                assert u.dtype == np.float64 and u.shape[1:] == (2,)
                assert_array_equal(u, np.asarray(v, dtype=np.float64).reshape(-1, 2))
        else:
            assert x.dtype == np.float64 and x.shape[1:] == (2,)
            assert_array_equal(x, np.asarray(y, dtype=np.float64).reshape(-1, 2))


# ------------------------------------------------------------------ round trips
def test_round_trip_single_sensor_is_exact(tmp_path):
    rng = np.random.default_rng(0)
    scans = [np.empty((0, 2)), rng.normal(0, 500, (3, 2)), [], rng.random((1, 2)) * 1e-300,
             np.array([[1e308, -0.0]]), np.empty((0, 2))]
    path = tmp_path / "single.csv"
    write_measurements(path, scans)
    back = read_measurements(path)
    assert_same_scans(back, scans)  # empty scans at both ends kept, floats bit for bit
    assert np.signbit(back[4][0, 1])
    assert path.read_text().splitlines()[:2] == ["scan,x,y", "1,,"]
    write_measurements(path, scans, first_scan=0)
    assert_same_scans(read_measurements(path), scans)
    assert_same_scans(read_measurements(path, first_scan=0), scans)


def test_round_trip_multi_sensor(tmp_path):
    rng = np.random.default_rng(1)
    scans = [(rng.random((2, 2)), np.empty((0, 2)), rng.random((1, 2))),
             ([], [], []),
             (rng.random((1, 2)), rng.random((4, 2)), [])]
    path = tmp_path / "multi.csv"
    write_measurements(path, scans, first_scan=5)
    back = read_measurements(path)
    assert all(isinstance(s, tuple) and len(s) == 3 for s in back)
    assert_same_scans(back, scans)
    assert path.read_text().splitlines()[0] == "scan,sensor,x,y"


def test_round_trip_of_a_scenario(tmp_path):
    sc = make_scenario("vo", rng=2, n_scans=20)
    path = tmp_path / "vo.csv"
    write_measurements(path, [s.z for s in sc.scans])
    assert_same_scans(read_measurements(path), [s.z for s in sc.scans])


# ------------------------------------------------------------------ the layout users have
def test_reading_the_layout_users_have(tmp_path):
    # a BOM, capitalised headers with spaces, columns in another order, an extra column, rows
    # out of scan order, blank lines, integral floats as scan numbers, a gap (scan 4)
    text = ("\ufeffX , Scan,y,origin\n"
            "1.5,3,2.5,7\n"
            "\n"
            "-4,5.0,1e3,-1\n"
            "2.5,3,-3.5,-1\n")
    path = write(tmp_path, text)
    scans = read_measurements(path)
    assert len(scans) == 3  # scans 3, 4, 5
    assert_array_equal(scans[0], [[1.5, 2.5], [2.5, -3.5]])  # the file's order within a scan
    assert scans[1].shape == (0, 2)
    assert_array_equal(scans[2], [[-4.0, 1000.0]])
    # numbered from 1: scans 1 and 2 are empty
    one = read_measurements(path, first_scan=1)
    assert [z.shape[0] for z in one] == [0, 0, 2, 0, 1]
    # a declared empty scan at the end
    path = write(tmp_path, "scan,x,y\n1,0,0\n4,,\n")
    assert [z.shape[0] for z in read_measurements(path)] == [1, 0, 0, 0]


def test_reading_several_sensors(tmp_path):
    path = write(tmp_path, "scan,sensor,x,y\n1,1,1,2\n1,0,3,4\n2,1,5,6\n2,1,7,8\n")
    scans = read_measurements(path)
    assert_same_scans(scans, [([[3, 4]], [[1, 2]]), ([], [[5, 6], [7, 8]])])
    three = read_measurements(path, n_sensors=3)
    assert [len(s) for s in three] == [3, 3] and three[0][2].shape == (0, 2)


# ------------------------------------------------------------------ errors name file and line
@pytest.mark.parametrize(("text", "message"), [
    ("", "{p}, line 1: the file is empty; a measurement file starts with a header row naming "
         "the columns scan, x, y"),
    ("scan,x\n1,2\n", "{p}, line 1: column 'y' missing from the header ['scan', 'x']; a "
                      "measurement file has the columns scan, x, y (and 'sensor' for several "
                      "sensors)"),
    ("t,px,py\n1,2,3\n", "{p}, line 1: columns 'scan', 'x', 'y' missing from the header "
                         "['t', 'px', 'py']"),
    ("scan,x,y,x\n1,2,3,4\n", "{p}, line 1: column 'x' appears 2 times in the header "
                              "['scan', 'x', 'y', 'x']"),
    ("scan,x,y\n", "{p}, line 1: no measurement rows after the header; a scan without "
                   "measurements is a row with x and y empty"),
    ("scan,x,y\n1,2,3\n2,abc,3\n", "{p}, line 3: x must be a number, got 'abc'"),
    ("scan,x,y\n1,2,NaN\n", "{p}, line 2: y must be a finite number, got 'NaN'"),
    ("scan,x,y\n1,inf,2\n", "{p}, line 2: x must be a finite number, got 'inf'"),
    ("scan,x,y\n1,2,\n", "{p}, line 2: y is missing (a row with both x and y empty declares a "
                         "scan without measurements)"),
    ("scan,x,y\n\n-1,2,3\n", "{p}, line 3: scan must be a non-negative integer, got '-1'"),
    ("scan,x,y\n1.5,2,3\n", "{p}, line 2: scan must be a non-negative integer, got '1.5'"),
    ("scan,x,y\nfirst,2,3\n", "{p}, line 2: scan must be a non-negative integer, got 'first'"),
    ("scan,x,y\nnan,2,3\n", "{p}, line 2: scan must be a non-negative integer, got 'nan'"),
    ("scan,x,y\n,2,3\n", "{p}, line 2: scan is missing"),
    ("scan,x,y\n1,2,3,4\n", "{p}, line 2: 4 fields, the header has 3"),
    ("scan,x,y\n1,2\n", "{p}, line 2: 2 fields, the header has 3"),
    ("scan,sensor,x,y\n1,-1,2,3\n", "{p}, line 2: sensor must be a non-negative integer, got "
                                    "'-1'"),
    ("scan,sensor,x,y\n1,,2,3\n", "{p}, line 2: sensor is missing"),
])
def test_read_errors(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ValueError, match=re.escape(message.format(p=path))):
        read_measurements(path)


def test_read_errors_of_the_options(tmp_path):
    path = write(tmp_path, "scan,sensor,x,y\n1,0,2,3\n2,2,2,3\n")
    with pytest.raises(ValueError, match=re.escape(
            f"{path}, line 3: sensor 2 is not an index in 0..1 (n_sensors = 2)")):
        read_measurements(path, n_sensors=2)
    with pytest.raises(ValueError, match=re.escape(
            f"{path}, line 2: scan 1 is before first_scan = 2")):
        read_measurements(path, first_scan=2)
    with pytest.raises(TypeError, match="first_scan must be an int"):
        read_measurements(path, first_scan=1.0)
    with pytest.raises(ValueError, match="n_sensors must be"):
        read_measurements(path, n_sensors=0)
    with pytest.raises(FileNotFoundError):
        read_measurements(tmp_path / "missing.csv")


def test_write_errors(tmp_path):
    path = tmp_path / "out.csv"
    with pytest.raises(TypeError, match="scans must be a sequence with one entry per scan, got "
                                        "int"):
        write_measurements(path, 3)
    with pytest.raises(ValueError, match="scans is empty: nothing to write"):
        write_measurements(path, [])
    with pytest.raises(TypeError, match=re.escape(
            "scans[1] is a tuple, scans[0] one array: every scan must be of the same kind")):
        write_measurements(path, [[[0.0, 1.0]], ([[0.0, 1.0]],)])
    with pytest.raises(TypeError, match=re.escape(
            "scans[1] is one array, scans[0] a tuple (one array per sensor): every scan must "
            "be of the same kind")):
        write_measurements(path, [([[0.0, 1.0]],), [[0.0, 1.0]]])
    with pytest.raises(ValueError, match=re.escape("scans[1] has 1 sensors, scans[0] has 2")):
        write_measurements(path, [([], []), ([],)])
    with pytest.raises(ValueError, match=re.escape(
            "measurements of scans[1] must have shape (M, 2), got shape (3,)")):
        write_measurements(path, [[], [1.0, 2.0, 3.0]])
    with pytest.raises(ValueError, match=re.escape(
            "measurements of scans[0], sensor 1 must be finite, got nan at [0, 1]")):
        write_measurements(path, [([], [[0.0, np.nan]])])
    with pytest.raises(TypeError, match="first_scan must be an int"):
        write_measurements(path, [[]], first_scan="1")
    assert not path.exists()  # nothing is written before every scan is checked


# ------------------------------------------------------------------ a filter run from a file
def test_run_filter_on_a_file_is_run_scenario(tmp_path):
    seed, n = 5, 15
    ref = run_scenario("vo", Exact(), rng=seed, n_scans=n, grouping=True)
    meas_rng, filter_rng = np.random.default_rng(seed).spawn(2)
    path = tmp_path / "vo.csv"
    write_measurements(path, [s.z for s in make_scenario("vo", rng=meas_rng, n_scans=n).scans])
    run = run_filter(LMBFilter(make_model("vo"), Exact(), grouping=True),
                     read_measurements(path), rng=filter_rng, truth=ref.truth)
    assert run.extraction == ref.extraction == "map"
    assert_array_equal(run.estimates, ref.estimates)
    assert run.estimate_labels == ref.estimate_labels
    assert run.existence == ref.existence
    assert_array_equal(run.n_meas, ref.n_meas)
    assert run.ospa2.value.shape == (n,)


def test_run_filter_on_a_multi_sensor_file_is_run_multisensor_scenario(tmp_path):
    seed, n, sensors = 1, 5, (0, 1)
    assoc = ShortChainGibbs(40, 10, tau_stall=5, tau_stale=10, method="exact")
    ref = run_multisensor_scenario(assoc, rng=seed, n_scans=n, sensors=sensors)
    meas_rng, filter_rng = np.random.default_rng(seed).spawn(2)
    sc = make_multisensor_scenario(rng=meas_rng, n_scans=n, sensors=sensors)
    path = tmp_path / "multi.csv"
    write_measurements(path, [tuple(s.z for s in per) for per in sc.scans])
    run = run_filter(MultiSensorLMBFilter(make_multisensor_model(sensors), assoc),
                     read_measurements(path), rng=filter_rng, truth=sc.truth)
    assert_array_equal(run.estimates, ref.estimates)
    assert run.existence == ref.existence
    assert_array_equal(run.sweeps, ref.sweeps)
    assert_array_equal(run.n_births, ref.n_births)


# ------------------------------------------------------------------ hostile files and arguments
@pytest.mark.parametrize(("text", "message"), [
    # two rows make a million scans plus one: refused with the memory, before it is built
    ("scan,x,y\n1,0,0\n1000001,0,0\n",
     "{p}, line 3: scan 1000001 makes 1000001 scans from first_scan = 1, above MAX_SCANS = "
     "1000000 (the bound of n_scans): the empty scans alone would need 129.7 MiB (136000136 "
     "bytes), 136 bytes a scan and sensor"),
    ("scan,x,y\n1000000000000,,\n1,0,0\n",
     "{p}, line 2: scan 1000000000000 makes 1000000000000 scans from first_scan = 1, above "
     "MAX_SCANS = 1000000"),
    ("scan,sensor,x,y\n1,0,0,0\n1,1000000000,0,0\n",
     "{p}, line 3: sensor 1000000000 makes 1000000001 sensors of 1 scan, 1000000001 "
     "measurement sets, above MAX_MEASUREMENT_SETS = 4000000 (MAX_SCANS scans of 4 sensors): "
     "the empty sets alone would need 126.7 GiB (136000000136 bytes), 136 bytes a set"),
    # not plain decimal integers: Python's int() takes all of these
    ("scan,x,y\n1_000,0,0\n", "{p}, line 2: scan must be a non-negative integer, got '1_000' "
                              "(decimal digits, as 3 or 3.0)"),
    ("scan,x,y\n+3,0,0\n", "{p}, line 2: scan must be a non-negative integer, got '+3'"),
    ("scan,x,y\n\u0663,0,0\n", "{p}, line 2: scan must be a non-negative integer, got '\u0663'"),
    ("scan,x,y\n1e3,0,0\n", "{p}, line 2: scan must be a non-negative integer, got '1e3'"),
    ("scan,sensor,x,y\n1,0_1,0,0\n", "{p}, line 2: sensor must be a non-negative integer, got "
                                     "'0_1'"),
    ("scan,x,y\n" + "9" * 5000 + ",0,0\n",
     "{p}, line 2: scan 999999999999999999... (5000 digits) is too large"),
    ("scan,x,y\n1,1_0.5,0\n", "{p}, line 2: x must be a plain decimal number (digits, a point, "
                              "an exponent), got '1_0.5'"),
    ("scan,x,y\n1,0,\u0661\n", "{p}, line 2: y must be a plain decimal number"),
    # the csv module's own errors name the file and the line
    ("scan,x,y\n1,0,0\n2," + "1" * 140_000 + ",0\n",
     "{p}, line 3: not a CSV row the reader can take: field larger than field limit (131072)"),
])
def test_hostile_files_are_refused_with_file_and_line(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ValueError, match=re.escape(message.format(p=path))):
        read_measurements(path)


def test_the_bounds_are_the_scenario_runners_and_hold_for_n_sensors_and_first_scan(
        tmp_path, monkeypatch):
    from rankedassign.tracking import io, scenario

    assert io.MAX_SCANS is scenario.MAX_SCANS == 10**6  # the bound of n_scans
    assert io.MAX_MEASUREMENT_SETS == 4 * 10**6  # MAX_SCANS scans of the 4 'multi' sensors
    path = write(tmp_path, "scan,sensor,x,y\n1,0,0,0\n")
    with pytest.raises(ValueError, match=re.escape(
            f"{path}, line 1: n_sensors = 10000000 of 1 scan, 10000000 measurement sets, above "
            "MAX_MEASUREMENT_SETS = 4000000")):
        read_measurements(path, n_sensors=10**7)
    # the bounds are inclusive (smaller bounds, so that the test builds little)
    monkeypatch.setattr(io, "MAX_SCANS", 5)
    monkeypatch.setattr(io, "MAX_MEASUREMENT_SETS", 10)
    path = write(tmp_path, "scan,x,y\n5,0,0\n")
    assert len(read_measurements(path, first_scan=1)) == 5
    with pytest.raises(ValueError, match=re.escape(
            f"{path}, line 2: scan 5 makes 6 scans from first_scan = 0, above MAX_SCANS = 5")):
        read_measurements(path, first_scan=0)
    path = write(tmp_path, "scan,sensor,x,y\n1,1,0,0\n5,0,,\n")
    assert [len(s) for s in read_measurements(path)] == [2] * 5
    path = write(tmp_path, "scan,sensor,x,y\n1,2,0,0\n5,0,,\n")
    with pytest.raises(ValueError, match=re.escape(
            f"{path}, line 2: sensor 2 makes 3 sensors of 5 scans, 15 measurement sets, above "
            "MAX_MEASUREMENT_SETS = 10")):
        read_measurements(path)


@pytest.mark.parametrize(("data", "line", "what"), [
    ("scan,x,y\n1,0,0\n2,\xe9,0\n".encode("latin-1"), 3, "byte e9 at column 3"),
    ("scan,x,y\n1,0,0\n".encode("utf-16"), 1, "byte ff at column 1"),  # the UTF-16 BOM
    ("scan,x,y\n1,0,0\n".encode("utf-16-be"), 1, "the header holds NUL characters: the file "
                                                  "is not UTF-8 text (UTF-16?)"),
    (b"\xef\xbb\xbfscan,x,y\n1,0,0\n" + b"1,0,0\n" * 5000 + b"7,\xff,0\n", 5003, "byte ff"),
])
def test_files_that_are_not_utf8_name_file_and_line(tmp_path, data, line, what):
    path = tmp_path / "meas.csv"
    path.write_bytes(data)
    if not what.startswith("the header"):
        what = f"the file is not UTF-8 text ({what}"
    with pytest.raises(ValueError, match=re.escape(f"{path}, line {line}: {what}")) as info:
        read_measurements(path)
    assert "save it as UTF-8" in str(info.value)


def test_n_sensors_without_a_sensor_column_is_refused(tmp_path):
    path = write(tmp_path, "scan,x,y\n1,0,0\n")
    for n in (1, 3):
        with pytest.raises(ValueError, match=re.escape(
                f"{path}, line 1: n_sensors = {n} is for a file with a 'sensor' column, and "
                "this one has none (its scans are one array each); leave n_sensors out")):
            read_measurements(path, n_sensors=n)
    assert [z.shape for z in read_measurements(path)] == [(1, 2)]


@pytest.mark.parametrize("bad", [3, 0, True, 3.0, None, [b"m.csv"]])
def test_a_path_that_is_no_path_is_refused(tmp_path, bad):
    # an int is a file descriptor to open(): reading it would read (and close) that descriptor
    kind = type(bad).__name__
    with pytest.raises(TypeError, match=re.escape(
            f"read_measurements: path must be a str or path-like (os.PathLike) naming a file, "
            f"got {kind}")):
        read_measurements(bad)
    with pytest.raises(TypeError, match=re.escape(
            f"write_measurements: path must be a str or path-like (os.PathLike) naming a file, "
            f"got {kind}")):
        write_measurements(bad, [[]])
    with pytest.raises(TypeError, match="an int is a file descriptor, which is not accepted"):
        read_measurements(3)
    path = write(tmp_path, "scan,x,y\n1,0,0\n")
    assert read_measurements(str(path))[0].shape == (1, 2)
    assert read_measurements(bytes(path))[0].shape == (1, 2)
