#!/usr/bin/env python
"""Mutation check (issue 26): change one named behaviour at a time and show that a test fails.

Each mutant is a small source edit (file, exact old text -> new text, the old text occurring exactly
once) and the pytest node ids that should catch it. The tree (``git ls-files`` plus the built
``meshmark/_core*.so``, from src/ or else the installed package) is copied to a temporary folder
once; every mutant is written into that copy, its tests run there (``PYTHONPATH=<copy>/src``, one
process), and the file restored from the pristine text before the next one. The working tree is never written to.

A mutant is *killed* when pytest exits 1 (a test failed); *survived* when it exits 0; any other exit
(collection error, usage error) is reported as *error*. The unmutated copy is run first on the union
of the node ids (``--no-baseline`` skips it): a test that fails already proves nothing.

Only Python sources are mutated, so no rebuild is needed. Development tool, not part of the test
suite (several minutes). Exit status: 0 every mutant killed, 1 otherwise, 2 bad arguments or a
mutant whose old text is not found exactly once.

    PYTHONPATH=src python tools/mutation_check.py            # all, a table on stdout
    python tools/mutation_check.py --only exit-not-found --markdown
"""
from __future__ import annotations

import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass

ROOT = pathlib.Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Mutant:
    name: str
    path: str
    old: str
    new: str
    tests: tuple


T_EXIT = "tests/test_cli_exit_codes.py"
T_ATT = "tests/test_attacks.py"
T_CHO = "tests/test_cho_steganalysis.py"
T_RAD = "tests/test_radial_watermark.py"
T_LAP = "tests/test_laplacian_watermark.py"
T_KA = "tests/test_known_answers.py"
T_TRACE = "tests/test_tracing.py::test_decision_at_the_threshold_and_the_bonferroni_pair"

MUTANTS = (
    Mutant("exit-not-found", "src/meshmark/cli.py", "= 0, 1, 2, 3", "= 0, 0, 2, 3",
           (f"{T_EXIT}::test_extract_detected_not_detected_and_input_error",)),
    Mutant("exit-input-error", "src/meshmark/cli.py", "= 0, 1, 2, 3", "= 0, 1, 1, 3",
           (f"{T_EXIT}::test_capacity_K_is_bounded",)),
    Mutant("exit-internal-error", "src/meshmark/cli.py", "= 0, 1, 2, 3", "= 0, 1, 2, 2",
           (f"{T_EXIT}::test_internal_error_is_status_3_without_traceback",)),
    Mutant("detection-threshold", "src/meshmark/watermark/framework.py", "DETECTION_THRESHOLD = 1e-6",
           "DETECTION_THRESHOLD = 1e-4", (f"{T_LAP}::test_too_few_carriers",)),
    Mutant("noise-strength", "src/meshmark/attacks/basic.py", "kind, A, _seed(seed))", "kind, 1.1 * A, _seed(seed))",
           (f"{T_ATT}::test_uniform_noise_bounds_statistics_and_seed",)),
    Mutant("quantization-step", "src/meshmark/attacks/basic.py", "_core.quantize(m.V, int(bits))",
           "_core.quantize(m.V, int(bits) - 1)", (f"{T_ATT}::test_quantize_by_hand",)),
    Mutant("smoothing-lambda", "src/meshmark/attacks/basic.py", "m.face_offsets, lam, int(iterations)",
           "m.face_offsets, 1.5 * lam, int(iterations)", (f"{T_ATT}::test_uniform_smoothing_one_step_by_hand",)),
    Mutant("similarity-translation", "src/meshmark/attacks/basic.py", "t = t * tr * float(",
           "t = t * tr * 0.5 * float(", (f"{T_ATT}::test_random_similarity_is_a_similarity_and_seeded",)),
    Mutant("key-derivation", "src/meshmark/watermark/keys.py", 'f"meshmark/v1/{method}/{label}/"',
           'f"meshmark/v2/{method}/{label}/"', (f"{T_KA}::test_carrier_permutation_and_whitening_are_shake256_of_the_documented_labels",)),
    Mutant("keyfile-tag-key", "src/meshmark/watermark/keyfile.py", 'b"meshmark-keyfile-tag/v1\\0"',
           'b"meshmark-keyfile-tag/v2\\0"', (f"{T_KA}::test_keyfile_tag_is_hmac_sha256_of_the_canonical_json",)),
    Mutant("cho-mean-alpha", "src/meshmark/watermark/cho.py", 'ALPHA = {"mean": 0.04', 'ALPHA = {"mean": 0.05',
           (f"{T_RAD}::test_cho_matches_reference",)),
    Mutant("radial-n-thr-power-law", "src/meshmark/watermark/radial.py", "return 0.0245 * n", "return 0.0255 * n",
           (f"{T_RAD}::test_default_n_thr_rule",)),
    Mutant("laplacian-default-n-thr", "src/meshmark/watermark/laplacian.py", '"n_thr": 46,', '"n_thr": 40,',
           (f"{T_LAP}::test_bunny_capacity_with_thesis_defaults",)),
    Mutant("cho-detector-p-value", "src/meshmark/steganalysis/cho.py",
           "rule: str | None = None,\n            false_alarm: float = 0.01,",
           "rule: str | None = None,\n            false_alarm: float = 0.05,",
           (f"{T_CHO}::test_margin_decision_follows_the_false_alarm_rate",)),
    Mutant("cho-balance-tolerance", "src/meshmark/steganalysis/cho.py", "if abs(k - n / 2) > t)",
           "if abs(k - n / 2) >= t)", (f"{T_CHO}::test_balance_tolerance_is_binomial",)),
    Mutant("stego-lsb-bit-count", "src/meshmark/stego/lsb.py", "np.maximum(0, 31 - np.asarray(i)[used])",
           "np.maximum(0, 30 - np.asarray(i)[used])", ("tests/test_stego.py::test_table_4_4_bunny_beside_the_thesis",)),
    Mutant("json-detected-field", "src/meshmark/watermark/framework.py", '{"detected": self.detected,',
           '{"found": self.detected,', (f"{T_LAP}::test_cli_embed_extract_capacity",)),
    Mutant("tracing-acceptance", "src/meshmark/watermark/tracing.py", "detected = bool(p < DETECTION_THRESHOLD)",
           "detected = bool(p < 1e-2)", (T_TRACE,)),
    Mutant("tracing-bonferroni", "src/meshmark/watermark/tracing.py", "p = min(1.0, 2.0 * min(p_blind, p_inf))",
           "p = min(1.0, min(p_blind, p_inf))", (T_TRACE,)),
    Mutant("laplacian-default-solver", "src/meshmark/watermark/laplacian.py", '"solver": "iterative",',
           '"solver": "direct",', (f"{T_LAP}::test_no_drift_and_distortion",)),
)


def _copy_tree(dest: pathlib.Path) -> None:
    files = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout.split(b"\0")
    for f in filter(None, files):
        src = ROOT / os.fsdecode(f)
        if src.is_file():
            (dest / os.fsdecode(f)).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, dest / os.fsdecode(f))
    for so in _built_core():
        shutil.copy2(so, dest / "src" / "meshmark" / so.name)


def _built_core() -> list:
    """The compiled module: beside the sources (a worktree) or else in the installed package (.venv)."""
    for d in [ROOT / "src"] + [pathlib.Path(p) for p in sys.path if p]:
        found = sorted((d / "meshmark").glob("_core*.so"))
        if found:
            return found
    raise SystemExit("no built meshmark/_core*.so beside src/ or on sys.path: build first (./test.sh)")


def _pytest(tree: pathlib.Path, tests, env) -> tuple[int, list, float]:
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-rf", "-p", "no:cacheprovider", *tests],
                       cwd=tree, env=env, capture_output=True, text=True)
    failed = re.findall(r"^FAILED (\S+)", r.stdout, flags=re.M)
    return r.returncode, failed, time.monotonic() - t0


def _check_texts(mutants) -> list:
    bad = []
    for m in mutants:
        n = (ROOT / m.path).read_text().count(m.old)
        if n != 1:
            bad.append(f"{m.name}: {m.old!r} occurs {n} times in {m.path} (must be exactly once)")
    return bad


def run(mutants, baseline: bool = True, out=print) -> list:
    """[(mutant, status, failing test or '', seconds)] for ``mutants``; status killed/survived/error."""
    env = dict(os.environ)
    env.setdefault("MESHMARK_SHARED", str(ROOT.parent / "shared"))
    rows = []
    with tempfile.TemporaryDirectory(prefix="meshmark-mutation-") as tmp:
        tree = pathlib.Path(tmp)
        _copy_tree(tree)
        env["PYTHONPATH"] = str(tree / "src")
        if baseline:
            union = sorted({t for m in mutants for t in m.tests})
            rc, failed, sec = _pytest(tree, union, env)
            if rc != 0:
                raise SystemExit(f"baseline failed (exit {rc}, {failed}): fix the tests before mutating")
            out(f"baseline: {len(union)} node ids pass on the unmutated tree ({sec:.0f} s)")
        for m in mutants:
            target = tree / m.path
            pristine = target.read_text()
            try:
                target.write_text(pristine.replace(m.old, m.new, 1))
                rc, failed, sec = _pytest(tree, m.tests, env)
            finally:
                target.write_text(pristine)
            status = {1: "killed", 0: "survived"}.get(rc, f"error (exit {rc})")
            rows.append((m, status, failed[0] if failed else "", sec))
            out(f"{m.name}: {status} in {sec:.1f} s {failed[0] if failed else ''}")
    return rows


def table(rows, markdown: bool) -> str:
    if markdown:
        lines = ["| behaviour | mutation | test that failed | seconds |", "|---|---|---|---|"]
        for m, status, test, sec in rows:
            what = f"`{m.path.removeprefix('src/meshmark/')}`: `{m.old}` → `{m.new}`".replace("|", "\\|")
            lines.append(f"| {m.name} | {what} | {test or status} | {sec:.1f} |")
        return "\n".join(lines)
    w = max(len(m.name) for m, *_ in rows)
    return "\n".join(f"{m.name:<{w}}  {status:<9} {sec:6.1f} s  {test}" for m, status, test, sec in rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", action="append", default=[], help="run this mutant (repeatable)")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    ap.add_argument("--no-baseline", action="store_true", help="skip the unmutated run")
    a = ap.parse_args(argv)
    names = {m.name for m in MUTANTS}
    unknown = set(a.only) - names
    if unknown:
        print(f"unknown mutant(s): {', '.join(sorted(unknown))}", file=sys.stderr)
        return 2
    chosen = [m for m in MUTANTS if not a.only or m.name in a.only]
    if a.list:
        for m in chosen:
            print(f"{m.name}: {m.path}: {m.old!r} -> {m.new!r}  [{' '.join(m.tests)}]")
        return 0
    bad = _check_texts(chosen)
    if bad:
        print("\n".join(bad), file=sys.stderr)
        return 2
    rows = run(chosen, baseline=not a.no_baseline, out=lambda s: print(s, file=sys.stderr))
    print(table(rows, a.markdown))
    survivors = [m.name for m, status, *_ in rows if status != "killed"]
    if survivors:
        print(f"not killed: {', '.join(survivors)}", file=sys.stderr)
    return 1 if survivors else 0


if __name__ == "__main__":
    sys.exit(main())
