"""`pip check`, less one known false report: the bpy 5.0.1 wheel for CPython 3.11 carries the tag
cp39-cp39-manylinux_2_28_x86_64 in its own WHEEL file, so pip >= 24 says "bpy 5.0.1 is not supported
on this platform" although pip installed it from the cp311 wheel and it imports. Any other line
(a missing or conflicting requirement) fails. Usage: python tools/pip_check.py  (exit 0 / 1)."""
import re
import subprocess
import sys

KNOWN = re.compile(r"^bpy 5\.0\.1 is not supported on this platform$")


def main() -> int:
    r = subprocess.run([sys.executable, "-m", "pip", "check"], capture_output=True, text=True)
    lines = [x for x in r.stdout.splitlines() + r.stderr.splitlines() if x.strip()]
    real = [x for x in lines if not KNOWN.match(x) and not x.startswith("No broken requirements")]
    for x in real:
        print(x)
    if real or (r.returncode != 0 and not any(KNOWN.match(x) for x in lines)):
        return 1
    if any(KNOWN.match(x) for x in lines):
        import importlib.util
        if importlib.util.find_spec("bpy") is None:  # the report is only excused for a bpy that imports
            print("bpy is reported unsupported and cannot be found")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
