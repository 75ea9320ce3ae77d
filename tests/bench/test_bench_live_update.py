"""bench/bench_live_update.py and bench_live_region.py inside Blender (background) on small
meshes: both domains, every part of an update timed; a proportional radius and its steps."""

import os
import shutil
import subprocess

import pytest

from _bench import BENCH, BUILD, ROOT, finite, load

BLENDER = shutil.which("blender", path="/usr/bin:/bin") or shutil.which("blender")


def run_in_blender(tmp_path, script, *args):
    """bench/<script> in Debian's Blender (background), with this build's package and add-on
    and throwaway user folders; fails with Blender's output unless it exits 0."""
    env = dict(os.environ, EDGEDEFORM_PYTHONPATH=str(BUILD / "python"),
               EDGEDEFORM_ADDON_DIR=str(ROOT / "addon"),
               BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"),
               BLENDER_USER_CONFIG=str(tmp_path / "config"),
               PATH="/usr/bin:/bin:" + os.environ.get("PATH", ""))
    proc = subprocess.run([BLENDER, "-b", "--factory-startup", "--python-exit-code", "1",
                           "--python", str(BENCH / script), "--", *map(str, args)],
                          capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.skipif(BLENDER is None, reason="Blender is not installed")
def test_live_update_in_blender(tmp_path):
    out = tmp_path / "live_update.json"
    run_in_blender(tmp_path, "bench_live_update.py", "--sizes", "1k", "--updates", "3", "--json", out)
    result = load(out)
    assert [r["domain"] for r in result["results"]] == ["edge", "primal"]
    for r in result["results"]:
        assert r["vertices"] == 829 and r["updates"] == 3
        times = [r[k] for k in ("bind_ms", "targets_ms", "solve_ms", "write_ms", "update_ms", "depsgraph_ms")]
        assert finite(*times) and all(t >= 0 for t in times) and r["update_ms"] > 0
    assert result["machine"]["blender"]
    import live_update_report
    assert "| spot_low_resolution.obj | 829 | edge |" in live_update_report.markdown(result)


@pytest.mark.skipif(BLENDER is None, reason="Blender is not installed")
def test_live_region_in_blender(tmp_path):
    """bench/bench_live_region.py on the small Spot split once, Proportional on: an update
    and a wheel step each way, the region's free vertices fewer than the mesh's."""
    out = tmp_path / "live_region.json"
    run_in_blender(tmp_path, "bench_live_region.py", "--mesh", "spot_low_resolution.obj", "--radius", "0.3",
                   "--updates", "3", "--json", out)
    result = load(out)
    (r,) = result["results"]
    assert 0 < r["free_vertices"] < r["vertices"] == 3310
    assert finite(r["update_ms"], r["radius_grow_ms"], r["radius_shrink_ms"]) and r["update_ms"] > 0
    import live_update_report
    assert "radius step" in live_update_report.region_markdown(result)
