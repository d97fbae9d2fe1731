"""tools/mutation_check.py stays usable: every mutant's old text is still in its file exactly once
and every test it names exists (a refactor that moves the text or renames the test shows here, not
only when someone runs the slow tool)."""
import importlib.util
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
spec = importlib.util.spec_from_file_location("mutation_check", ROOT / "tools" / "mutation_check.py")
mc = importlib.util.module_from_spec(spec)
sys.modules["mutation_check"] = mc  # the dataclasses resolve their module by name
spec.loader.exec_module(mc)


def test_twenty_mutants_whose_texts_are_found_once():
    assert len(mc.MUTANTS) == 20 and len({m.name for m in mc.MUTANTS}) == 20
    assert mc._check_texts(mc.MUTANTS) == []


def test_every_named_test_exists():
    for m in mc.MUTANTS:
        for node in m.tests:
            path, _, name = node.partition("::")
            fn = name.split("[")[0]
            assert f"def {fn}(" in (ROOT / path).read_text(), (m.name, node)
