"""Keep the best policy seen during training, judged on validation episodes of its own task.

Off-policy agents on these tasks do not improve monotonically: a run can succeed on every
validation episode and fail them all a hundred episodes later. The RL Zoo's answer is
``EvalCallback(best_model_save_path=...)``; :class:`KeepBestOnValidation` does the same for a
single-environment, episode-budgeted run: every ``every`` training episodes it runs ``n_episodes``
deterministic episodes on the training task (seeds ``seed + i``, the evaluation library's start
noise) and keeps a copy of the policy's weights when their success rate beats every earlier check
(ties go to the higher mean return). :meth:`restore` puts the best copy back into the model. The
validation seeds must differ from the final evaluation's, so that the reported success rate is
measured on episodes nothing was chosen on.
"""

from __future__ import annotations

import copy
from typing import Any

from stable_baselines3.common.callbacks import BaseCallback

#: First validation seed: apart from the training seeds (0..) and the study's evaluation seeds
#: (10000..).
VALIDATION_SEED = 20_000
#: Training episodes between two checks, and episodes per check, by default (the study's).
VALIDATION_EVERY = 25
VALIDATION_EPISODES = 30


def validation_rank(check: dict[str, Any]) -> tuple[float, float]:
    """How checks are ranked (a later check is kept only when it ranks strictly higher):
    success rate, then mean return, of one ``history`` entry of :class:`KeepBestOnValidation`."""
    return (float(check["success_rate"]), float(check["mean_return"]))


class KeepBestOnValidation(BaseCallback):
    """Validate every ``every`` episodes on ``env_id``; keep the best weights (see the module).

    Args:
        env_id: the task to validate on (normally the training task).
        every: training episodes between two checks (>= 1; default 25).
        n_episodes: validation episodes per check (>= 1; default 30).
        env_kwargs: keyword arguments of the validation environment (not ``start_noise``;
            default: those the model trains with).
        seed: first validation seed.
        restore_at_end: put the best weights back into the model when ``learn`` ends
            (:meth:`restore`), so that the model saved next is the one kept.
    """

    def __init__(
        self,
        env_id: str,
        every: int = VALIDATION_EVERY,
        n_episodes: int = VALIDATION_EPISODES,
        env_kwargs: dict[str, Any] | None = None,
        seed: int = VALIDATION_SEED,
        restore_at_end: bool = True,
    ) -> None:
        super().__init__(verbose=0)
        for name, value in (("every", every), ("n_episodes", n_episodes)):
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f"{name}={value!r} is not allowed: expected an integer >= 1")
        self.env_id = env_id
        self.every = every
        self.n_episodes = n_episodes
        self.env_kwargs = dict(env_kwargs or {})
        self.seed = seed
        self.restore_at_end = bool(restore_at_end)
        self.episodes = 0
        #: One entry per check: {"episode", "success_rate", "mean_return"}.
        self.history: list[dict[str, float]] = []
        self.best_episode: int | None = None
        self._best_key: tuple[float, float] | None = None
        self._best_state: dict[str, Any] | None = None

    def _on_step(self) -> bool:
        for done in self.locals["dones"]:
            if done:
                self.episodes += 1
                if self.episodes % self.every == 0:
                    self.check()
        return True

    def _on_training_end(self) -> None:
        if self.restore_at_end:
            self.restore()

    def check(self) -> None:
        """Validate the model now; keep its weights if they are the best so far."""
        from sb3_pnn.evaluation import evaluate_policy_on_task

        result = evaluate_policy_on_task(
            self.model,
            self.env_id,
            n_episodes=self.n_episodes,
            seed=self.seed,
            env_kwargs=self.env_kwargs or None,
        )
        entry = {
            "episode": self.episodes,
            "success_rate": result.success_rate,
            "mean_return": result.mean_return,
        }
        self.history.append(entry)
        key = validation_rank(entry)
        if self._best_key is None or key > self._best_key:
            self._best_key = key
            self.best_episode = self.episodes
            self._best_state = copy.deepcopy(self.model.policy.state_dict())

    def restore(self) -> bool:
        """Load the best weights into the model; False (and nothing changed) if none was kept."""
        if self._best_state is None:
            return False
        self.model.policy.load_state_dict(self._best_state)
        return True

    def to_dict(self) -> dict[str, Any]:
        """The checks and the chosen episode (JSON-able)."""
        return {
            "every": self.every,
            "n_episodes": self.n_episodes,
            "seed": self.seed,
            "history": self.history,
            "best_episode": self.best_episode,
        }
