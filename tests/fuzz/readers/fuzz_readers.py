"""Coverage-guided fuzzing of one mesh reader with atheris (libFuzzer for Python):

    python3 fuzz_readers.py EXT CORPUS [MORE_CORPORA...] [libFuzzer flags]

EXT is .obj, .off or .ply; every input goes through oracle.check, inside an address space
512 MB larger than the fuzzer's own when it starts (a reader that asks for more raises
MemoryError: a finding). tests/fuzz/run_fuzz_readers.sh runs it for ctest.
"""

import resource
import sys

import atheris

with atheris.instrument_imports(include=["edgedeform"]):
    import edgedeform.mesh_files  # noqa: F401  (instrumented: the readers and what they call)

import oracle  # noqa: E402

READER_ADDRESS_SPACE = 512 << 20


def address_space_in_use():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    raise RuntimeError("no VmSize in /proc/self/status")


def main():
    ext = sys.argv.pop(1)
    limit = address_space_in_use() + READER_ADDRESS_SPACE
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    atheris.Setup(sys.argv, lambda data: oracle.check(data, ext))
    atheris.Fuzz()


if __name__ == "__main__":
    main()
