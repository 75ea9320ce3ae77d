"""Last of the bpy tests: which Blender versions passed which suites in this run.

    check_bpy_results.py RESULTS_DIR MIN_VERSION [MIN_VERSION ...]

Fails unless, for each MIN_VERSION, at least one Blender >= MIN_VERSION passed a suite: a run
whose bpy versions were all skipped (none installable) must not look green, and neither
must one where only the cp311 Blender releases ran on a machine that has Python 3.13.
"""

import os
import sys

results = sys.argv[1]
passed = {}
for name in sorted(os.listdir(results)) if os.path.isdir(results) else []:
    if name.endswith(".pass"):
        version, suite = name[:-len(".pass")].split("-", 1)
        passed.setdefault(version, []).append(suite)
for version, suites in sorted(passed.items()):
    print("Blender %s (bpy): passed %s" % (version, ", ".join(suites)))
failed = False
for text in sys.argv[2:]:
    minimum = tuple(int(x) for x in text.split("."))
    if not [v for v in passed if tuple(int(x) for x in v.split(".")[:2]) >= minimum]:
        print("FAILED: no Blender >= %s passed a suite in this run (its bpy skipped?)" % text)
        failed = True
sys.exit(1 if failed else 0)
