"""SIGKILL at random moments of ``meshmark embed --force`` (used by tests/test_file_safety.py, 40 kills,
and bench/kill_embed.py, 200). After each kill the pair at the output paths must be the old mesh
with its old keyfile, the new mesh with its new keyfile, or the old mesh beside the new keyfile
(the keyfile is renamed first); never a new mesh beside an old or missing keyfile. A complete run
after a kill must leave no meshmark temporary in the folder. Not a test module."""
from __future__ import annotations

import hashlib
import json
import os
import random
import signal
import subprocess
import sys
import time

from meshmark import atomic

PY = sys.executable
CLI = [PY, "-m", "meshmark"]


def run(args, cwd=None, umask=None, **kw):
    pre = (lambda: os.umask(umask)) if umask is not None else None
    return subprocess.run(CLI + [str(a) for a in args], capture_output=True, text=True, timeout=120, cwd=cwd,
                          preexec_fn=pre, **kw)


def temps(folder) -> list:
    """The meshmark temporaries (of any process) in ``folder``."""
    return sorted(n for n in os.listdir(folder) if atomic._STALE.match(n))


def _digest(p):
    return hashlib.sha256(p.read_bytes()).hexdigest() if p.exists() else None


def _keyfile_key(p):
    """The key a keyfile was written with (its bytes differ per run: 'created'); None if missing."""
    return json.loads(p.read_text())["key"] if p.exists() else None


def kill_run(src, out, kf, keys, n_kills, seed, full_every, on_state=None):
    """SIGKILL ``embed --force`` at random moments (uniform over a full run, and half of them in its
    last quarter, where the files are written); after each kill the pair at (out, kf) must be the old
    pair, the new pair, or the old mesh beside the new keyfile. Every ``full_every`` kills one complete
    run must leave no temporary. Returns counts of the states seen."""
    folder = out.parent
    ref = {}
    for k in keys:  # the mesh each key gives (embed is deterministic); a keyfile names its key
        r = run(["embed", src, out, "--keyfile", kf, "--key", k, "--message", "m", "--force"])
        assert r.returncode == 0, r.stderr
        ref[k] = _digest(out)
    times = []
    for _ in range(3):  # the length of a full run: the median of the last timed complete runs
        t0 = time.perf_counter()
        run(["embed", src, out, "--keyfile", kf, "--key", keys[0], "--message", "m", "--force"])
        times.append(time.perf_counter() - t0)
    full = sorted(times)[1]
    by_mesh = {v: k for k, v in ref.items()}
    assert len(by_mesh) == len(keys)
    state = (keys[0], keys[0])
    rnd = random.Random(seed)
    delays = []
    seen = {"unchanged": 0, "new": 0, "old mesh + new keyfile": 0, "temporaries left": 0, "full runs clean": 0,
            "run had ended before the kill": 0}
    for i in range(n_kills):
        new = keys[1] if state[1] == keys[0] else keys[0]
        delay = rnd.uniform(0, full) if i % 2 == 0 else rnd.uniform(0.75 * full, 1.05 * full)
        p = subprocess.Popen(CLI + ["embed", str(src), str(out), "--keyfile", str(kf), "--key", new, "--message", "m",
                                    "--force"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        delays.append(delay / full)
        time.sleep(delay)
        seen["run had ended before the kill"] += p.poll() is not None
        p.send_signal(signal.SIGKILL)
        p.wait()
        m, k = by_mesh.get(_digest(out)), _keyfile_key(kf)
        assert m is not None and k is not None, f"kill {i} at {delay:.3f} s: a mesh or keyfile that is neither old nor new"
        if (m, k) == state:
            seen["unchanged"] += 1
        elif (m, k) == (new, new):
            seen["new"] += 1
        elif (m, k) == (state[0], new):
            seen["old mesh + new keyfile"] += 1
        else:
            raise AssertionError(f"kill {i} at {delay:.3f} s: mesh of key {m} beside the keyfile of key {k} "
                                 f"(before: {state}, the run wrote {new})")
        state = (m, k)
        if on_state:
            on_state(i, delay, (m, k))
        seen["temporaries left"] += bool(temps(folder))
        if (i + 1) % full_every == 0:
            new = keys[1] if state[1] == keys[0] else keys[0]
            t0 = time.perf_counter()
            r = run(["embed", src, out, "--keyfile", kf, "--key", new, "--message", "m", "--force"])
            times.append(time.perf_counter() - t0)
            full = sorted(times[-5:])[len(times[-5:]) // 2]  # follows the machine's load
            assert r.returncode == 0, r.stderr
            assert temps(folder) == [], f"after kill {i} and a complete run: {temps(folder)}"
            state = (new, new)
            seen["full runs clean"] += 1
    seen["delay fraction min/median/max"] = [round(min(delays), 3), round(sorted(delays)[len(delays) // 2], 3),
                                          round(max(delays), 3)]
    seen["full run seconds min/median/max"] = [round(min(times), 3), round(sorted(times)[len(times) // 2], 3),
                                            round(max(times), 3)]
    return seen, full


