"""``rig walk`` end to end on a short walk, its JSON schema, and bad input."""

import json

import numpy as np
import pytest

from rig.main import main
from rig.walk import ALL_METHODS


@pytest.fixture(scope="module")
def short_walk(tmp_path_factory):
    out = tmp_path_factory.mktemp("walk")
    rc = main(["walk", "--looks", "3", "--out", str(out / "o"), "--json", str(out / "w.json"),
               "--quiet"])
    return rc, out


def test_rig_walk_end_to_end(short_walk, capsys):
    rc, out = short_walk
    assert rc == 0
    doc = json.loads((out / "w.json").read_text())
    assert [lk["look"] for lk in doc["looks"]] == [0, 1, 2]
    assert set(doc["method_names"]) == set(ALL_METHODS)
    for lk in doc["looks"]:
        assert set(lk["true"]) == {"x", "z", "heading_deg"}
        assert set(lk["methods"]) == set(ALL_METHODS)
        for m in lk["methods"].values():
            assert {"x", "z", "heading_deg", "position_error_ft", "heading_error_deg"} <= set(m)
    # look 0 is the given start; the table's truth is the bundled walk's
    from world.walk import bundled_walk
    assert doc["looks"][0]["methods"]["a48"]["position_error_ft"] == 0.0
    for lk, pose in zip(doc["looks"], bundled_walk()):
        assert (lk["true"]["x"], lk["true"]["z"], lk["true"]["heading_deg"]) == pytest.approx(
            (pose.x, pose.z, pose.heading_deg))
    robust = doc["looks"][1]["methods"]["robust"]
    assert robust["position_error_ft"] < 0.5 and robust["heading_error_deg"] < 3.0
    model = doc["model"]
    assert model["features"] > 50 and 0 <= model["inside_2sigma"] <= 1
    assert model["rms_error_ft"] > 0
    full = json.loads((out / "o" / "model.json").read_text())
    assert len(full["model_tables"]["vertices"]) == model["features"]
    ply = (out / "o" / "model.ply").read_text()
    assert f"element vertex {model['features']}" in ply
    body = ply.split("end_header\n", 1)[1].strip().splitlines()
    assert len(body) == model["features"]
    first = full["model_tables"]["vertices"][0]
    np.testing.assert_allclose([float(v) for v in body[0].split()[:3]], first["mean"], atol=1e-4)
    for name in ("map.png", "errors.png"):
        assert (out / "o" / name).stat().st_size > 1000
    assert not [p for p in (out / "o").iterdir() if p.name.startswith(".")]


def test_bad_walk_row_is_one_clear_error(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("x,z,heading_deg,pitch_deg,roll_deg\n0,0,0,0,0\n0.5,zero,0,0,0\n")
    out = tmp_path / "o"
    rc = main(["walk", "--walk", str(bad), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "bad.csv" in err and "line 3" in err
    assert not out.exists()


def test_pose_outside_the_room_is_refused(tmp_path, capsys):
    walk = tmp_path / "out.csv"
    walk.write_text("x,z,heading_deg,pitch_deg,roll_deg\n0,0,0,0,0\n40,0,0,0,0\n")
    rc = main(["walk", "--walk", str(walk), "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2 and "pose 1" in err and "outside the room" in err
    assert not (tmp_path / "o").exists()


def test_too_few_looks_is_refused(tmp_path, capsys):
    rc = main(["walk", "--looks", "1", "--out", str(tmp_path / "o"), "--quiet"])
    assert rc == 2 and "at least 2 looks" in capsys.readouterr().err


def test_unwritable_outputs_are_refused_before_walking(tmp_path, capsys):
    rc = main(["walk", "--looks", "2", "--out", str(tmp_path / "o"), "--json",
               str(tmp_path / "nowhere" / "w.json"), "--quiet"])
    assert rc == 2 and "no such directory" in capsys.readouterr().err
    (tmp_path / "file").write_text("x")
    rc = main(["walk", "--looks", "2", "--out", str(tmp_path / "file"), "--quiet"])
    assert rc == 2 and "not a directory" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_rig_walk_with_honest_covariance_options(tmp_path, short_walk):
    # the named options end to end: A-29 with the calibrated column error and the measured
    # pose floor; the settings are in the JSON and the covariances are covariances
    out = tmp_path / "o"
    rc = main(["walk", "--looks", "3", "--kalman", "a29", "--column-error", "calibrated",
               "--pose-floor", "measured", "--out", str(out), "--json", str(tmp_path / "w.json"),
               "--quiet"])
    assert rc == 0
    doc = json.loads((tmp_path / "w.json").read_text())
    assert doc["column_error_px"] == 2.0 and doc["pose_sigma_floor"] == [0.13, 0.85]
    assert doc["kalman"] == "a29"
    default = json.loads((short_walk[1] / "w.json").read_text())
    assert default["column_error_px"] == 0.5 and default["pose_sigma_floor"] is None
    full = json.loads((out / "model.json").read_text())
    for v in full["model_tables"]["vertices"]:
        assert np.linalg.eigvalsh(np.array(v["cov"])).min() > -1e-6
    # wider, honest covariances hold at least as many truths as LCSL's on the same looks
    assert doc["model"]["inside_2sigma"] >= default["model"]["inside_2sigma"]


@pytest.mark.parametrize("opt", [["--column-error", "0"], ["--column-error", "wide"],
                                 ["--pose-floor", "0.1"], ["--pose-floor", "x,1"]])
def test_bad_honest_covariance_values_are_refused(opt, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["walk", *opt, "--quiet"])
    assert exc.value.code == 2
    assert opt[0] in capsys.readouterr().err


def test_rig_walk_with_consider_covariance_and_feature_gate(tmp_path, short_walk):
    # the named options end to end on the short walk: the pose and the filter are the A-29
    # walk's (the consider covariance is only reported), the settings and both shares are in
    # the JSON, every reported covariance is a covariance
    out = tmp_path / "o"
    rc = main(["walk", "--looks", "3", "--kalman", "a29", "--consider", "bound",
               "--feature-gate", "--retire-unseen", "1", "--out", str(out), "--json",
               str(tmp_path / "w.json"), "--quiet"])
    assert rc == 0
    doc = json.loads((tmp_path / "w.json").read_text())
    assert doc["consider"] == "bound" and doc["feature_gate"] == pytest.approx(16.27)
    assert doc["retire_unseen"] == 1
    m = doc["model"]
    assert m["inside_2sigma"] >= m["filter_inside_2sigma"]
    assert m["retired"] >= 0
    full = json.loads((out / "model.json").read_text())
    for v in full["model_tables"]["vertices"]:
        assert np.linalg.eigvalsh(np.array(v["report_cov"])).min() > 0
    default = json.loads((short_walk[1] / "w.json").read_text())
    assert default["consider"] is None and default["feature_gate"] is None
    # the consider covariance alone never reaches the filter, the matcher or the pose: the
    # same walk under plain A-29 gives the same poses and the same model to the digit
    rc = main(["walk", "--looks", "3", "--kalman", "a29", "--consider", "bound", "--out",
               str(tmp_path / "c"), "--json", str(tmp_path / "c.json"), "--quiet"])
    rc2 = main(["walk", "--looks", "3", "--kalman", "a29", "--out", str(tmp_path / "p"),
                "--json", str(tmp_path / "p.json"), "--quiet"])
    assert rc == rc2 == 0
    c, p = (json.loads((tmp_path / n).read_text()) for n in ("c.json", "p.json"))
    assert [lk["methods"]["fused"] for lk in c["looks"]] == [lk["methods"]["fused"]
                                                             for lk in p["looks"]]
    assert c["model"]["rms_error_ft"] == p["model"]["rms_error_ft"]
    assert c["model"]["filter_inside_2sigma"] == p["model"]["inside_2sigma"]
    assert default["retire_unseen"] is None and default["model"]["retired"] == 0


@pytest.mark.parametrize("opt", [["--feature-gate", "0"], ["--feature-gate", "x"],
                                 ["--consider", "wide"], ["--retire-unseen", "0"]])
def test_bad_consider_and_gate_values_are_refused(opt, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["walk", *opt, "--quiet"])
    assert exc.value.code == 2
    assert opt[0] in capsys.readouterr().err


def test_consider_with_covariance_intersection_is_refused(tmp_path, capsys):
    rc = main(["walk", "--looks", "2", "--kalman", "ci", "--consider", "bound",
               "--out", str(tmp_path / "o"), "--quiet"])
    assert rc == 2 and "--consider" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_rig_walk_variance_factor_tilt_floor_and_confirmation_keep_a29(tmp_path):
    # the reporting options end to end: the poses, the means and the filter's covariances
    # are plain A-29's to the digit (they only widen or sort what is reported); the settings
    # and the new shares are in the JSON, every vertex carries its innovations
    rc = main(["walk", "--looks", "4", "--kalman", "a29", "--consider", "bound",
               "--tilt-floor", "measured", "--variance-factor", "--confirm", "--out",
               str(tmp_path / "v"), "--json", str(tmp_path / "v.json"), "--quiet"])
    rc2 = main(["walk", "--looks", "4", "--kalman", "a29", "--out", str(tmp_path / "p"),
                "--json", str(tmp_path / "p.json"), "--quiet"])
    rc3 = main(["walk", "--looks", "4", "--kalman", "a29", "--consider", "bound", "--out",
                str(tmp_path / "c"), "--json", str(tmp_path / "c.json"), "--quiet"])
    assert rc == rc2 == rc3 == 0
    v, p, c = (json.loads((tmp_path / n).read_text()) for n in ("v.json", "p.json", "c.json"))
    assert v["tilt_floor"] == [0.32, 3.2] and v["variance_factor"] is True and v["confirm"] == 2
    assert p["tilt_floor"] is None and p["variance_factor"] is False and p["confirm"] is None
    assert [lk["methods"]["fused"] for lk in v["looks"]] == [lk["methods"]["fused"]
                                                             for lk in p["looks"]]
    vm = json.loads((tmp_path / "v" / "model.json").read_text())["model_tables"]["vertices"]
    pm = json.loads((tmp_path / "p" / "model.json").read_text())["model_tables"]["vertices"]
    cm = json.loads((tmp_path / "c" / "model.json").read_text())["model_tables"]["vertices"]
    assert [x["mean"] for x in vm] == [x["mean"] for x in pm]
    assert [x["cov"] for x in vm] == [x["cov"] for x in pm]
    # the same looks fused (their NIS are against the wider covariances: smaller)
    assert [len(x["nis"]) for x in vm] == [len(x["nis"]) for x in cm] == [x["looks"] - 1
                                                                         for x in vm]
    assert any(x["nis"] for x in vm)
    assert sum(map(sum, (x["nis"] for x in vm))) < sum(map(sum, (x["nis"] for x in cm)))
    # the tilt floor only widens the consider covariance (the bound's weight is chosen by the
    # trace, so the trace is what grows; the vertical most)
    for a, b in zip(vm, cm):
        assert np.trace(a["report_cov"]) >= np.trace(b["report_cov"]) - 1e-6
    assert sum(a["report_cov"][1][1] for a in vm) > sum(b["report_cov"][1][1] for b in cm)
    m = v["model"]
    assert m["track_confirmed"] + m["tentative"] == m["scored"]
    assert m["variance_factor_global"] > 0
    assert m["inside_2sigma"] >= c["model"]["inside_2sigma"]
    assert m["rms_error_ft"] == p["model"]["rms_error_ft"]
    assert "track_confirmed" not in p["model"]


@pytest.mark.parametrize("opt", [["--confirm", "1"], ["--confirm", "x"],
                                 ["--tilt-floor", "0.3"], ["--tilt-floor", "x,1"]])
def test_bad_confirm_and_tilt_floor_values_are_refused(opt, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["walk", *opt, "--quiet"])
    assert exc.value.code == 2
    assert opt[0] in capsys.readouterr().err


def test_tilt_floor_without_the_consider_covariance_is_refused(tmp_path, capsys):
    rc = main(["walk", "--looks", "2", "--kalman", "a29", "--tilt-floor", "measured",
               "--out", str(tmp_path / "o"), "--quiet"])
    assert rc == 2 and "--tilt-floor" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_rig_walk_ambiguity_gate_drop_and_track(tmp_path):
    # the ambiguity gate end to end on the first looks of the bundled walk (the bookcase's
    # binders and the left wall's chart are periodic): "drop" takes the ambiguous vertices
    # out of the looks, "track" keeps them for matching but starts no feature with them
    runs = {}
    for name, extra in (("p", []), ("d", ["--ambiguity-gate", "drop"]),
                        ("t", ["--ambiguity-gate", "track"])):
        rc = main(["walk", "--looks", "6", "--kalman", "a29", *extra, "--out",
                   str(tmp_path / name), "--json", str(tmp_path / f"{name}.json"), "--quiet"])
        assert rc == 0
        runs[name] = json.loads((tmp_path / f"{name}.json").read_text())
    p, d, t = runs["p"], runs["d"], runs["t"]
    assert p["ambiguity_gate"] is None and "ambiguous" not in p["looks"][0]
    assert d["ambiguity_gate"] == "drop" and t["ambiguity_gate"] == "track"
    amb = [lk["ambiguous"] for lk in t["looks"]]
    assert amb == [lk["ambiguous"] for lk in d["looks"]] and amb[0] > 0
    # the scan does not depend on the pose: "track" sees every vertex the plain walk
    # sees, "drop" fewer wherever there was an ambiguous one
    assert [lk["seen"] for lk in t["looks"]] == [lk["seen"] for lk in p["looks"]]
    for lp, ld, a in zip(p["looks"], d["looks"], amb):
        assert ld["seen"] <= lp["seen"] - (1 if a else 0)
    # the first look matches nothing: the plain walk adds every vertex, "track" all but the
    # ambiguous, "drop" exactly what it saw
    assert p["looks"][0]["added"] == p["looks"][0]["seen"]
    assert t["looks"][0]["added"] == d["looks"][0]["added"] == d["looks"][0]["seen"]
    assert t["looks"][0]["added"] < p["looks"][0]["added"]


def test_rig_walk_ambiguity_gate_resolve(tmp_path):
    # "resolve" end to end on the first looks of the bundled walk: at the first look nothing
    # predicts a period, so it starts exactly what "track" starts; later looks report how
    # many ambiguous edges the model's prediction moved to another period
    runs = {}
    for name in ("track", "resolve"):
        rc = main(["walk", "--looks", "6", "--kalman", "a29", "--ambiguity-gate", name,
                   "--out", str(tmp_path / name), "--json", str(tmp_path / f"{name}.json"),
                   "--quiet"])
        assert rc == 0
        runs[name] = json.loads((tmp_path / f"{name}.json").read_text())
    t, r = runs["track"], runs["resolve"]
    assert r["ambiguity_gate"] == "resolve" and "resolved" not in t["looks"][0]
    assert r["looks"][0]["resolved"] == 0 and r["looks"][0]["ambiguous"] > 0
    assert r["looks"][0]["added"] == t["looks"][0]["added"]
    assert all(lk["resolved"] >= 0 for lk in r["looks"])
    assert r["looks"][0]["seen"] == t["looks"][0]["seen"]
