"""The study of Pan et al. (2025), section 4.3, as one resumable command.

``python -m sb3_pnn.reproduce [--quick]`` (see :mod:`.cli`). Modules: :mod:`.plan` (which runs,
with which budgets), :mod:`.executor` (parallel runs in dependency order), :mod:`.store`
(resume bookkeeping: atomic run folders with manifests), :mod:`.work` (train/evaluate one run),
:mod:`.recorder` (episode-budget callback), :mod:`.stats`, :mod:`.results`, :mod:`.figures` and
:mod:`.report`.
"""

from sb3_pnn.reproduce.planning.plan import Budget, RunSpec, StudyConfig, build_plan

__all__ = ["Budget", "RunSpec", "StudyConfig", "build_plan"]
