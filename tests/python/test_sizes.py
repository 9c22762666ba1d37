"""scripts/indepsim/sizes.py: a level's size is its ratio to the calibrated (reference) model, and a
ratio to a reference level at a bound of its box is flagged as one-sided (issue 18's size target is
"relative to the calibrated model")."""
import json
import os
import subprocess
import sys

SIZES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "indepsim", "sizes.py")


def write_case(root, value, initial, baseline_at_bound, as_class=False):
    """A corpus directory with one stiffness-level recording named right (the report's layout); with
    as_class, named as the class tooth_contact_change fitted as the level (the level check's form)."""
    (root / "g").mkdir()
    (root / "truth.json").write_text(json.dumps({"recordings": {
        "g/rec_01": {"effect": "stiffness_level", "parameters": {"stiffness_scale": 0.75}}}}))
    rep = root / "diagnosis" / "g" / "rec_01"
    rep.mkdir(parents=True)
    rep.joinpath("report.json").write_text(json.dumps({
        "missing_physics": "tooth_contact_change" if as_class else "stiffness_level",
        "finding_class": {"name": "tooth_contact_change", "members": ["stiffness_level", "damping_level", "friction"],
                          "size": []} if as_class else None,
        "lead": {"name": "stiffness_level"}, "baseline_at_bound": baseline_at_bound,
        "candidates": [{"name": "stiffness_level", "parameters": [{
            "name": "stiffness.scale", "value": value, "std_error": 0.02, "model_form_std": 0.0,
            "model_form_range": [None, None], "lower": 0.5 * initial, "upper": 2 * initial, "initial": initial}]}]}))


def run(root):
    out = root / "rows.json"
    subprocess.run([sys.executable, SIZES, str(root), "--json", str(out)], check=True, capture_output=True, text=True)
    return json.loads(out.read_text())["rows"]


def test_a_level_is_scored_as_its_ratio_to_the_reference_not_as_its_absolute_value(tmp_path):
    write_case(tmp_path, value=1.5, initial=2.0, baseline_at_bound=[])
    (row,) = run(tmp_path)
    assert abs(row["fitted"] - 0.75) < 1e-12          # 1.5 / 2, not 1.5
    assert abs(row["std_error"] - 0.01) < 1e-12
    assert abs(row["severity_error"]) < 1e-12         # the truth 0.75 exactly
    assert row["conditional_on"] is None


def test_a_ratio_to_a_reference_level_at_its_bound_is_flagged_one_sided(tmp_path):
    write_case(tmp_path, value=1.742, initial=2.0, baseline_at_bound=["stiffness.scale at its upper bound 2"])
    (row,) = run(tmp_path)
    assert abs(row["fitted"] - 0.871) < 1e-12
    assert "limit" in row["conditional_on"] and "one-sided" in row["conditional_on"]


def test_a_class_named_through_the_true_level_is_scored_by_that_levels_ratio(tmp_path):
    write_case(tmp_path, value=1.5, initial=2.0, baseline_at_bound=[], as_class=True)
    (row,) = run(tmp_path)
    assert row["effect"] == "stiffness_level (class)"
    assert abs(row["fitted"] - 0.75) < 1e-12


def test_a_class_fitted_as_another_member_gets_no_size_row(tmp_path):
    write_case(tmp_path, value=1.5, initial=2.0, baseline_at_bound=[], as_class=True)
    rep = tmp_path / "diagnosis" / "g" / "rec_01" / "report.json"
    r = json.loads(rep.read_text())
    r["lead"] = {"name": "friction"}
    r["candidates"][0]["name"] = "friction"
    rep.write_text(json.dumps(r))
    assert run(tmp_path) == []
