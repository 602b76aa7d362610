"""The quick subset of every cross-code check (the same code `make validate`
runs in full), so that `make test` catches regressions against the real codes."""

import pytest

from validation.checks import modules
from validation.shared.check import Context


@pytest.mark.parametrize("module", modules(), ids=lambda m: m.__name__.rsplit(".", 1)[-1])
def test_quick_checks_pass(module, tmp_path):
    results = module.run(Context(out_dir=tmp_path, quick=True))
    assert results, "a check module must return at least one check"
    failed = [f"{c.name}: measured {c.measured:.3g} > tolerance {c.tolerance:.3g} ({c.details})" for c in results if not c.passed]
    assert not failed, "\n".join(failed)
