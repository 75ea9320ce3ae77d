"""Checks of a demo run (tests/demo/CMakeLists.txt runs the demo with --ci first):
the sheet exists, is not blank, differs between λ=0 and λ=1; the metrics JSON has every cell.
    python3 -m pytest tests/demo/test_demo_outputs.py with DEMO_OUT=DIR"""
import json
import math
import os
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path[:0] = [os.path.join(REPO, "demo"), os.path.join(REPO, "blend_samples")]
import png  # noqa: E402

CELLS = ["edge_0", "edge_0.5", "edge_1", "primal_0", "primal_0.5", "primal_1", "painted_edge"]
METRICS = ["handle_error", "mean_edge_strain", "max_edge_strain", "mean_dihedral_change",
           "arap_energy", "iterations", "ms"]


@pytest.fixture(scope="module")
def doc():
    out = os.environ.get("DEMO_OUT")
    assert out, "set DEMO_OUT to the demo's output folder"
    with open(os.path.join(out, "metrics.json")) as f:
        d = json.load(f)
    assert d["samples"], "no sample in metrics.json"
    return d


@pytest.fixture(scope="module")
def sheets(doc):
    return {s["name"]: png.read_png(s["sheet"]).astype(float) for s in doc["samples"]}


def crop(img, box):
    x, y, w, h = box
    return img[y:y + h, x:x + w]


def test_metrics_has_every_cell(doc):
    for s in doc["samples"]:
        assert [c["key"] for c in s["cells"]] == CELLS
        for c in s["cells"]:
            for k in METRICS:
                assert isinstance(c[k], (int, float)) and math.isfinite(c[k]), (c["key"], k)
            assert c["iterations"] >= 1
            assert c["handle_error"] < 1e-6, "handles must sit on their targets"


def test_markdown_table_has_every_cell(doc):
    md = open(os.path.join(os.environ["DEMO_OUT"], "metrics.md")).read()
    for s in doc["samples"]:
        for key in CELLS:
            assert "| %s |" % key in md


def test_sheet_not_blank(doc, sheets):
    for s in doc["samples"]:
        img = sheets[s["name"]]
        assert set(s["sheet_cells"]) == set(CELLS) | {"rest"}
        for key, box in s["sheet_cells"].items():
            cell = crop(img, box)
            assert cell.shape[:2] == (box[3], box[2])
            # a blank (single-colour) render has zero variance; a shaded mesh has plenty
            assert cell.mean(axis=2).std() > 5.0, (s["name"], key)


@pytest.mark.parametrize("domain", ["edge", "primal"])
def test_sheet_differs_between_lambda_0_and_1(doc, sheets, domain):
    for s in doc["samples"]:
        img, boxes = sheets[s["name"]], s["sheet_cells"]
        a, b = crop(img, boxes[domain + "_0"]), crop(img, boxes[domain + "_1"])
        # ignore the label strip (it shows the iteration count and timing, which differ anyway)
        top = a.shape[0] // 5
        changed = np.abs(a[top:] - b[top:]).max(axis=2) > 24
        assert changed.mean() > 0.005, (s["name"], domain, changed.mean())


def test_results_blend_written(doc):
    assert os.path.getsize(os.path.join(os.environ["DEMO_OUT"], "edgedeform_results.blend")) > 0


def test_addon_agrees_with_package(doc):
    for s in doc["samples"]:
        check = s.get("addon_check")
        if check is None:
            pytest.skip("demo run without the add-on check")
        assert check["ok"], check
