"""The prior KL term on copies of each minibatch that read drawn obstacles (not in the paper).

A learner trained on one fixed layout replays the sonar readings of that layout's few obstacles
only, so ``prior_kl`` (with ``near_reference_prior``: toward the obstacle-avoidance prior near an
obstacle) holds its new column to the avoidance prior on those readings alone; among the
obstacles of a new layout the new column reads patterns it never trained on and is free to
override the prior that learned them (docs/ablation, sections 43 and 63). This term adds

    beta_obs * mean_s' KL(pi(.|s') || pi_0(.|s'))

over copies s' of the minibatch's states whose sonar also sees 1-3 cylinders drawn at random
around the vehicle (the reading of each sector is the smaller of the replayed one and the drawn
obstacles' one). Their sizes are those of the avoidance task's own random fields
(``rov_envs.sim.layouts``' ``scatter``: radius U(0.75, 2.5) m), their surfaces between eq. 21's
collision distance and the sonar's range, their bearings anywhere in its span. The other
observation parts, the path part included, are the sampled states' own, so the reference pi_0
of each copy is what the policy's KL term picks there: the avoidance prior where a drawn
obstacle is nearer than the clearance (and the copy inside the corridor bound), the
path-following prior elsewhere.

The sector geometry is the simulator's (``rov_envs.physics.sonar``), written for batches of
torch tensors: a sector reads the nearest point of a circle inside its wedge, which is the
circle's radially closest point when that lies in the wedge, or else the nearest crossing of
the circle with one of the wedge's two edge rays.
"""

from __future__ import annotations

import math

import torch as th

#: Drawn cylinders per copy (inclusive range).
OBSTACLES_PER_COPY = (1, 3)
#: Their radius (m): the avoidance task's random fields' (``rov_envs.sim.layouts``, scatter).
RADIUS_RANGE = (0.75, 2.5)
#: Nearest drawn surface (m): eq. 21's collision distance, which ends an episode.
NEAREST_SURFACE = 2.0


def sector_distances(
    bearing: th.Tensor, centre: th.Tensor, radius: th.Tensor, sectors: int, span: float
) -> th.Tensor:
    """Sector readings (m; ``inf`` where a sector does not see it) of circles around a vehicle.

    :param bearing: (B, M) relative bearings of the circles' centres (rad, + = to the left)
    :param centre: (B, M) distances from the vehicle to the centres (m), larger than ``radius``
    :param radius: (B, M) radii (m)
    :param sectors: q, sectors ordered from the vehicle's right (-span / 2) to its left
    :param span: the sonar's span S (rad)
    :return: (B, q) the nearest surface point of any circle inside each sector's wedge
    """
    width = span / sectors
    edges = -0.5 * span + width * th.arange(sectors + 1, dtype=bearing.dtype, device=bearing.device)
    delta = edges.view(1, 1, -1) - bearing.unsqueeze(2)  # (B, M, q + 1): edge ray - centre
    c, r = centre.unsqueeze(2), radius.unsqueeze(2)
    disc = r * r - (c * th.sin(delta)) ** 2
    cos_d = th.cos(delta)
    hits = (cos_d > 0) & (disc >= 0)
    t = th.where(hits, c * cos_d - th.sqrt(disc.clamp(min=0.0)), th.full_like(disc, math.inf))
    on_edges = th.minimum(t[..., :-1], t[..., 1:])  # (B, M, q): each sector's two edge rays
    inside = (bearing.unsqueeze(2) >= edges[:-1]) & (bearing.unsqueeze(2) <= edges[1:])
    radial = (centre - radius).unsqueeze(2).expand_as(on_edges)
    per_circle = th.where(inside, th.minimum(radial, on_edges), on_edges)
    return per_circle.min(dim=1).values


def drawn_sonar(
    n: int,
    sectors: int,
    span: float,
    max_range: float,
    generator: th.Generator | None = None,
    dtype: th.dtype = th.float32,
    device: th.device | str = "cpu",
) -> th.Tensor:
    """(n, q) sonar parts (reading / ``max_range``, 1 = nothing in range) of 1-3 cylinders drawn
    around a vehicle: radius in :data:`RADIUS_RANGE`, surface distance uniform in
    [:data:`NEAREST_SURFACE`, ``max_range``], relative bearing uniform in the span. A circle
    not drawn (fewer than three) lies beyond the range."""
    low, most = OBSTACLES_PER_COPY
    draws = th.rand(n, most, 3, generator=generator, dtype=th.float64)
    counts = th.randint(low, most + 1, (n, 1), generator=generator)
    present = th.arange(most).view(1, -1) < counts
    radius = RADIUS_RANGE[0] + (RADIUS_RANGE[1] - RADIUS_RANGE[0]) * draws[..., 0]
    surface = NEAREST_SURFACE + (max_range - NEAREST_SURFACE) * draws[..., 1]
    surface = th.where(present, surface, th.full_like(surface, 10.0 * max_range))
    bearing = (draws[..., 2] - 0.5) * span
    reading = sector_distances(bearing, surface + radius, radius, sectors, span)
    return (reading.clamp(max=max_range) / max_range).to(dtype=dtype, device=device)


def obstacle_copies(
    obs: dict[str, th.Tensor],
    sonar_key: str,
    span: float,
    max_range: float,
    generator: th.Generator | None = None,
) -> dict[str, th.Tensor]:
    """Copies of a batch of Dict observations whose sonar part also reads drawn obstacles
    (:func:`drawn_sonar`): each sector the smaller of its replayed and its drawn reading."""
    sonar = obs[sonar_key]
    drawn = drawn_sonar(
        sonar.shape[0], sonar.shape[1], span, max_range, generator, sonar.dtype, sonar.device
    )
    return {**obs, sonar_key: th.minimum(sonar, drawn)}
