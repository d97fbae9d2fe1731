"""Keyfile mutations (issue 23): 5,000 seeded mutations of real keyfiles of every method (laplacian
with three carriers/modes, radial with the keyed and the convolutional code, cho-mean, cho-variance,
a key-less keyfile) in versions 3, 2 and 1, each run through the real CLI (``meshmark extract``) in
its own forked child; 20 of them also through ``python -m meshmark`` in a subprocess, which must give
the same status and error text. No case may exit 3, print a traceback, hang, fail without a
``meshmark: error:`` line, or say "detected" for a file that is not the original's content (an
untagged file with a changed but valid value cannot be told apart: counted, and it must still read
the original key and payload). The engine is tests/keyfile_fuzz.py."""
import json
import os
import subprocess
import sys

from conftest import shared_mesh

HERE = os.path.dirname(os.path.abspath(__file__))


def test_5000_keyfile_mutations():
    shared_mesh("classic/cow.obj")  # the bases are embedded into it
    r = subprocess.run([sys.executable, os.path.join(HERE, "keyfile_fuzz.py"), "--cases", "5000", "--seed", "23",
                        "--subprocess", "20"], capture_output=True, text=True, timeout=1200)
    assert r.stdout, r.stderr[-3000:]
    d = json.loads(r.stdout)
    assert d["cases"] == 5000 and len(d["bases"]) == 22
    assert set(d["bases"].values()) == {0}, d["bases"]  # every unmutated keyfile detects its mark
    assert d["failures"] == [], json.dumps(d["failures"][:5], indent=1)
    assert set(d["exit_codes"]) <= {"0", "1", "2"}, d["exit_codes"]
    # the mutations are not all fatal and not all harmless
    assert d["exit_codes"]["2"] >= 3500 and d["exit_codes"].get("0", 0) >= 100 and d["exit_codes"].get("1", 0) >= 10
    assert d["subprocess_checked"] == 20 and d["subprocess_mismatches"] == [], d["subprocess_mismatches"][:3]
    print(f"keyfile mutations: exit codes {d['exit_codes']}, verdicts {d['verdicts']}, {d['seconds']} s")
