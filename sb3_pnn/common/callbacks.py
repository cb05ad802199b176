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

With ``drawn_episodes`` > 0 each check also runs that many episodes of the same task among
obstacles drawn afresh every episode (``layout=drawn_layout``, seeds ``drawn_seed + i``), and a
check ranks by its own-task success, then its success among the drawn obstacles, then its mean
return: of the policies that solve their task equally well, the one that also passes obstacles
it never trained on is kept. This is model selection on a validation distribution, as early
stopping is; it changes nothing in training.

Every check also records how closely the policy kept its route on those episodes (mean abs(g),
the cross-track error in metres, and mean abs(a_c), the heading error in radians). With
``rank_by="route"`` a check ranks, after its success (and its drawn success), by the smaller
mean abs(g) instead of the larger return: on the planning tasks the reward's obstacle term
(paper eq. 20) pays for detours that keep 8 m from every obstacle, so of two checks that solve
the task the one with the larger return is often the one that leaves the route wider. With
``rank_by="time"`` it ranks by the shorter mean time to the target of its successful episodes
instead: a policy that alternates hard turns near obstacles crosses them slowly, and on fields
denser than its training task runs out of time. With ``rank_by="discounted"`` it ranks by the
larger mean discounted return sum_t gamma^t r_t (gamma the model's): the quantity SAC maximises
from the start state. With r_c paid in proportion to progress (``progress_weighted``), the
undiscounted return pays a path follower the same for the path whatever its pace, so a check
that creeps along the path by alternating turns can outrank one that follows it as closely at
full speed; discounting charges for the pace.

With a ``route_bound`` (metres), of the checks of equal success (and drawn success) those whose
mean abs(g) is within the bound rank above those that leave it, and the ranking above decides
within each group: the kept policy is the best by return of those that keep the route within
the bound, and the best by return overall when none does. Eq. 20 pays for detours wider than a
user may want (docs/ablation section 100); the bound states the route wanted, and the return
still chooses among the routes that keep it.

With ``rank_by="last"`` every check outranks the ones before it, whatever its success: the
policy kept is the last one, as without checks, with the checks still recorded. On the sine
planning task SPNN's route narrows as it trains while its return peaks earlier, so the last
policy keeps the route closer than the return-best one (docs/ablation section 103).

With ``also_rank_by`` the callback keeps, beside the policy its own ranking chooses, the best
policy by each further ranking (without a route bound), from the same checks of the same
training: ``restore("route")`` puts the route-best one into the model, ``restore()`` the one
``rank_by`` chose. Which ranking to keep can then be compared on one training run instead of
one run per ranking; training and the policy ``rank_by`` keeps are the same as without it.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from typing import Any

from stable_baselines3.common.callbacks import BaseCallback

from sb3_pnn.common.checks import is_finite_number

#: First validation seed: apart from the training seeds (0..) and the study's evaluation seeds
#: (10000..).
VALIDATION_SEED = 20_000
#: Training episodes between two checks, and episodes per check, by default (the study's).
VALIDATION_EVERY = 25
VALIDATION_EPISODES = 30
#: First seed of the checks among drawn obstacles: apart from the validation seeds above, on
#: which :mod:`sb3_pnn.reproduce.tools.drawn_layouts` measures the kept policies afterwards.
DRAWN_VALIDATION_SEED = 30_000
#: The obstacle generator of those checks (none of the new layouts' generators).
DRAWN_VALIDATION_LAYOUT = "scatter"
#: What breaks a tie of success between two checks: the larger mean return (the default), the
#: smaller mean abs(g) (the route kept closer), the shorter mean time to the target or the
#: larger mean discounted return; "last" keeps the latest check whatever its success.
RANKINGS = ("return", "route", "time", "discounted", "last")
#: The check entry each ranking reads after the success, and its sign (+1: larger ranks higher).
_RANKED_ENTRY = {
    "return": ("mean_return", 1.0),
    "route": ("mean_abs_cross_track", -1.0),
    "time": ("mean_time_to_target", -1.0),
    "discounted": ("mean_discounted_return", 1.0),
    "last": ("episode", 1.0),
}


def checked_ranking(rank_by: Any) -> str:
    """``rank_by`` if it is one of :data:`RANKINGS`, else a ValueError naming it."""
    if rank_by not in RANKINGS:
        raise ValueError(f"rank_by={rank_by!r} is not allowed: expected one of {list(RANKINGS)}")
    return str(rank_by)


def ranked_entry(rank_by: str) -> str:
    """The validation check's entry that ``rank_by`` ranks by after the success."""
    return _RANKED_ENTRY[checked_ranking(rank_by)][0]


def checked_route_bound(route_bound: Any) -> float | None:
    """``route_bound`` as a float if it is a finite number > 0 (metres), None if None, else a
    ValueError naming it."""
    if route_bound is None:
        return None
    if not is_finite_number(route_bound) or route_bound <= 0:
        raise ValueError(
            f"route_bound={route_bound!r} is not allowed: expected a mean abs(g) in metres > 0, "
            "or None for no bound"
        )
    return float(route_bound)


def validation_rank(
    check: dict[str, Any], rank_by: str = "return", route_bound: float | None = None
) -> tuple[float, ...]:
    """How checks are ranked (a later check is kept only when it ranks strictly higher):
    success rate, then (when the check ran them) the success among drawn obstacles, then (with
    a ``route_bound``) whether its mean abs(g) is within the bound, then mean
    return (``rank_by="return"``), minus mean abs(g) (``"route"``), minus the mean time to the
    target (``"time"``; a check without a success ranks last) or the mean discounted return
    (``"discounted"``), of one ``history`` entry of
    :class:`KeepBestOnValidation`; ``"last"`` ranks by the check's episode alone (the latest
    check is kept, whatever its success)."""
    key, sign = _RANKED_ENTRY[checked_ranking(rank_by)]
    route_bound = checked_route_bound(route_bound)
    if rank_by == "last":  # the latest check, whatever its success
        return (float(check["episode"]),)
    if key not in check:
        raise ValueError(
            f"validation check {check!r} has no {key!r}: ranking by {rank_by} needs checks "
            "that recorded it"
        )
    last = -float("inf") if check[key] is None else sign * float(check[key])
    rank: tuple[float, ...] = (float(check["success_rate"]),)
    if "drawn_success_rate" in check:
        rank += (float(check["drawn_success_rate"]),)
    if route_bound is not None:
        rank += (float(float(check["mean_abs_cross_track"]) <= route_bound),)
    return rank + (last,)


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
        drawn_episodes: episodes per check among drawn obstacles (>= 0; 0, the default: none).
        drawn_layout: their obstacle generator (:mod:`rov_envs.sim.layouts`).
        drawn_seed: their first seed.
        rank_by: what ranks checks of equal success (:data:`RANKINGS`; :func:`validation_rank`).
        route_bound: mean abs(g) in metres within which a check ranks above checks of equal
            success that leave it (None, the default: no bound; see the module).
        also_rank_by: further rankings (:data:`RANKINGS`, no route bound), each keeping its own
            best policy for :meth:`restore` (default: none).
    """

    def __init__(
        self,
        env_id: str,
        every: int = VALIDATION_EVERY,
        n_episodes: int = VALIDATION_EPISODES,
        env_kwargs: dict[str, Any] | None = None,
        seed: int = VALIDATION_SEED,
        restore_at_end: bool = True,
        drawn_episodes: int = 0,
        drawn_layout: str = DRAWN_VALIDATION_LAYOUT,
        drawn_seed: int = DRAWN_VALIDATION_SEED,
        rank_by: str = "return",
        route_bound: float | None = None,
        also_rank_by: Sequence[str] = (),
    ) -> None:
        super().__init__(verbose=0)
        for name, value, least in (
            ("every", every, 1),
            ("n_episodes", n_episodes, 1),
            ("drawn_episodes", drawn_episodes, 0),
        ):
            if isinstance(value, bool) or not isinstance(value, int) or value < least:
                raise ValueError(f"{name}={value!r} is not allowed: expected an integer >= {least}")
        from rov_envs.sim.layouts import LAYOUT_CODES

        if drawn_layout not in LAYOUT_CODES:
            raise ValueError(
                f"drawn_layout={drawn_layout!r} is not allowed: expected one of "
                f"{sorted(LAYOUT_CODES)} (rov_envs.sim.layouts)"
            )
        self.env_id = env_id
        self.every = every
        self.n_episodes = n_episodes
        self.env_kwargs = dict(env_kwargs or {})
        self.seed = seed
        self.restore_at_end = bool(restore_at_end)
        self.drawn_episodes = drawn_episodes
        self.drawn_layout = str(drawn_layout)
        self.drawn_seed = int(drawn_seed)
        self.rank_by = checked_ranking(rank_by)
        self.route_bound = checked_route_bound(route_bound)
        if isinstance(also_rank_by, str) or not isinstance(also_rank_by, Sequence):
            raise ValueError(
                f"also_rank_by={also_rank_by!r} is not allowed: expected a sequence of rankings "
                f"from {list(RANKINGS)}, e.g. ('route', 'last')"
            )
        self.also_rank_by = tuple(checked_ranking(ranking) for ranking in also_rank_by)
        #: Per further ranking: (its rank of the check kept, that check's episode, its weights).
        self._also_kept: dict[str, tuple[tuple[float, ...], int, dict[str, Any]]] = {}
        self.episodes = 0
        #: One entry per check: {"episode", "success_rate", "mean_return",
        #: "mean_abs_cross_track", "mean_abs_heading_error", "mean_time_to_target"} and, with
        #: ``drawn_episodes``, "drawn_success_rate"; ranked by the discounted return,
        #: "mean_discounted_return".
        self.history: list[dict[str, float]] = []
        self.best_episode: int | None = None
        self._best_key: tuple[float, ...] | None = None
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

        # the discount is asked for only when it ranks, so that other checks run as before
        rankings = (self.rank_by, *self.also_rank_by)
        discount = {"discount": float(self.model.gamma)} if "discounted" in rankings else {}
        result = evaluate_policy_on_task(
            self.model,
            self.env_id,
            n_episodes=self.n_episodes,
            seed=self.seed,
            env_kwargs=self.env_kwargs or None,
            **discount,
        )
        entry = {
            "episode": self.episodes,
            "success_rate": result.success_rate,
            "mean_return": result.mean_return,
            "mean_abs_cross_track": result.mean_abs_cross_track,
            "mean_abs_heading_error": result.mean_abs_heading_error,
            "mean_time_to_target": result.mean_time_to_target,
        }
        if discount:
            entry["mean_discounted_return"] = result.mean_discounted_return
        if self.drawn_episodes:
            from sb3_pnn.evaluation.evaluate import trained_env_kwargs

            base = self.env_kwargs or trained_env_kwargs(self.model, self.env_id)
            drawn = evaluate_policy_on_task(
                self.model,
                self.env_id,
                n_episodes=self.drawn_episodes,
                seed=self.drawn_seed,
                env_kwargs={**base, "layout": self.drawn_layout},
            )
            entry["drawn_success_rate"] = drawn.success_rate
        self.history.append(entry)
        copied: list[dict[str, Any]] = []  # this check's weights, copied once for every ranking

        def weights() -> dict[str, Any]:
            if not copied:
                copied.append(copy.deepcopy(self.model.policy.state_dict()))
            return copied[0]

        key = validation_rank(entry, self.rank_by, self.route_bound)
        if self._best_key is None or key > self._best_key:
            self._best_key = key
            self.best_episode = self.episodes
            self._best_state = weights()
        for ranking in self.also_rank_by:
            key = validation_rank(entry, ranking)
            kept = self._also_kept.get(ranking)
            if kept is None or key > kept[0]:
                self._also_kept[ranking] = (key, self.episodes, weights())

    def restore(self, ranking: str | None = None) -> bool:
        """Load the best weights into the model: those ``rank_by`` chose, or with ``ranking``
        (one of ``also_rank_by``) that ranking's best; False (and nothing changed) if none was
        kept yet."""
        if ranking is None:
            state = self._best_state
        elif ranking in self.also_rank_by:
            state = self._also_kept[ranking][2] if ranking in self._also_kept else None
        else:
            raise ValueError(
                f"ranking={ranking!r} is not allowed: this callback keeps a policy for "
                f"{list(self.also_rank_by)} beside rank_by (ranking=None)"
            )
        if state is None:
            return False
        self.model.policy.load_state_dict(state)
        return True

    def to_dict(self) -> dict[str, Any]:
        """The checks and the chosen episode (JSON-able)."""
        data: dict[str, Any] = {
            "every": self.every,
            "n_episodes": self.n_episodes,
            "seed": self.seed,
            "history": self.history,
            "best_episode": self.best_episode,
        }
        if self.drawn_episodes:
            data.update(
                drawn_episodes=self.drawn_episodes,
                drawn_layout=self.drawn_layout,
                drawn_seed=self.drawn_seed,
            )
        if self.rank_by != "return":
            data["rank_by"] = self.rank_by
        if self.route_bound is not None:
            data["route_bound"] = self.route_bound
        if self.also_rank_by:
            data["best_episode_by"] = {
                ranking: self._also_kept[ranking][1] if ranking in self._also_kept else None
                for ranking in self.also_rank_by
            }
        return data
