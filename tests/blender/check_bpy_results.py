"""Last of the bpy tests: which Blender versions passed which suites in this run.

    check_bpy_results.py RESULTS_DIR MIN_VERSION

Fails unless at least one Blender >= MIN_VERSION passed a suite: a run whose bpy versions
were all skipped (none installable) must not look green.
"""

import os
import sys

results, minimum = sys.argv[1], tuple(int(x) for x in sys.argv[2].split("."))
passed = {}
for name in sorted(os.listdir(results)) if os.path.isdir(results) else []:
    if name.endswith(".pass"):
        version, suite = name[:-len(".pass")].split("-", 1)
        passed.setdefault(version, []).append(suite)
for version, suites in sorted(passed.items()):
    print("Blender %s (bpy): passed %s" % (version, ", ".join(suites)))
recent = [v for v in passed if tuple(int(x) for x in v.split(".")[:2]) >= minimum]
if not recent:
    print("FAILED: no Blender >= %s ran a suite in this run (all bpy versions skipped?)"
          % sys.argv[2])
    sys.exit(1)
