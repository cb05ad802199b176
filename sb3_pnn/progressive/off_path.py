"""The prior KL term on off-path copies of each minibatch (not in the paper).

``prior_kl`` (:class:`sb3_pnn.ProgressivePolicy`) keeps the new policy near its priors' policy
pi_0 on the replayed states only. A learner that keeps its path rarely replays states far off
it, so there its new column is free to output anything, and SPNN's can turn away from the
path where its path-following prior turns back (docs/ablation section 59). This term adds

    beta_off * mean_s' KL(pi(.|s') || pi_0(.|s'))

over copies s' of the minibatch's states whose "path" part [a_c / pi, g / d_L] is redrawn far
off the path (|g| / d_L uniform in :data:`OFF_PATH_BAND`, either side; a_c uniform within
+-90 deg, the heading rule's bound) and whose sonar reads clear (every sector at its range), so
that SPNN's gate selects the path-following prior and pi_0 is that prior's policy. The other
observation parts are the sampled states' own.

``clear_kl`` (PNN) uses copies that keep the path part and only clear the sonar: the replayed
states as they would read with no obstacle in range, where a PNN's path-following prior is the
reference of its KL term (``prior_kl_clearance``), so that what the new column learns near
obstacles does not spill over into how it follows the path in open water.
"""

from __future__ import annotations

from collections.abc import Sequence

import torch as th

#: Where the copies lie: |g| as a fraction of the corridor half-width d_L (the task ends at 1).
OFF_PATH_BAND = (0.3, 1.0)
#: The course error's bound, as the "path" part stores it (a_c / pi): +-90 deg.
HEADING_BOUND = 0.5
PATH_KEY = "path"


def off_path_copies(
    obs: dict[str, th.Tensor],
    sonar_key: str | None,
    zeroed_keys: Sequence[str] = (),
    generator: th.Generator | None = None,
    redraw_path: bool = True,
) -> dict[str, th.Tensor]:
    """Copies of a batch of Dict observations placed far off the path with a clear sonar.

    :param obs: (B, ...) tensors by key, with a ``"path"`` part [a_c / pi, g / d_L]
    :param sonar_key: the sonar's key, set to 1 (nothing within range); None: no sonar
    :param zeroed_keys: parts set to 0 (e.g. an obstacle latch: no obstacle remembered)
    :param generator: torch generator of the draws (None: torch's global one)
    :param redraw_path: False: the path part is kept (the copies only read a clear sonar)
    """
    copies = dict(obs)
    if sonar_key is not None and sonar_key in obs:
        copies[sonar_key] = th.ones_like(obs[sonar_key])
    for key in zeroed_keys:
        copies[key] = th.zeros_like(obs[key])
    if not redraw_path:
        return copies
    path = obs[PATH_KEY]
    n, dtype, device = path.shape[0], path.dtype, path.device
    draws = th.rand(n, 3, generator=generator, dtype=dtype, device=device)
    low, high = OFF_PATH_BAND
    side = th.where(draws[:, 2] < 0.5, -1.0, 1.0).to(dtype)
    heading = (2 * draws[:, 0] - 1) * HEADING_BOUND
    offset = side * (low + (high - low) * draws[:, 1])
    copies[PATH_KEY] = th.stack([heading, offset], dim=1)
    return copies
