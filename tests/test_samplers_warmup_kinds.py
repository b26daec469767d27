"""``samplers.warmup`` compiles the samplers of every kind of ``KINDS``: a new kind is not
missed silently."""

from __future__ import annotations

import rankedassign.samplers as samplers
from rankedassign.kinds import KINDS


def test_warmup_reaches_every_kind_with_every_sampler(monkeypatch):
    seen = {}
    for name in ("sample_original", "sample_short_chains"):
        real = getattr(samplers, name)

        def spy(problem, *args, _real=real, _name=name, **kwargs):
            seen.setdefault(_name, set()).add(type(problem))
            return _real(problem, *args, **kwargs)

        monkeypatch.setattr(samplers, name, spy)
    samplers.warmup()
    kinds = {k.problem_type for k in KINDS}
    assert seen == {"sample_original": kinds, "sample_short_chains": kinds}
