"""Hypothesis budgets. The profile, chosen by GPP_HYPOTHESIS, sets how many examples a property
test runs: `ci` (`make test`) as many as hypothesis runs by default, `dev` (the default, for
`make quick` and a local loop) about a tenth. A test that needs more or fewer than the others
says how many it runs under `ci` with `examples(n)`, which the profile scales.

Neither profile has a deadline: how long one example takes depends on the machine's load
(tests never assert times), and a run with `-n auto` shares the cores."""

from __future__ import annotations

import os

from hypothesis import settings

CI_EXAMPLES = 100  # hypothesis' default
PROFILES = {"ci": CI_EXAMPLES, "dev": CI_EXAMPLES // 10}
VARIABLE = "GPP_HYPOTHESIS"


def load_profile() -> str:
    """Register the profiles and load the one GPP_HYPOTHESIS names (`dev` when unset)."""
    for name, count in PROFILES.items():
        settings.register_profile(name, max_examples=count, deadline=None)
    name = os.environ.get(VARIABLE) or "dev"
    if name not in PROFILES:
        raise ValueError(f"{VARIABLE}={name!r}: the hypothesis profiles are {', '.join(PROFILES)}")
    settings.load_profile(name)
    return name


def examples(ci: int) -> int:
    """The number of examples of a test that runs `ci` of them under the `ci` profile."""
    return max(1, ci * settings.default.max_examples // CI_EXAMPLES)
