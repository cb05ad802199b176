"""Top-down ``rgb_array`` pictures of an rov_envs episode, drawn with numpy alone (fast).

Shows the path and its |g| = d_L corridor, the obstacles (filled) with their 2 m collision
margin (ring), the sonar sectors (boundary rays, and each sector's return as a dot), the
trajectory so far and the vehicle with its heading. x grows to the right, y (left of the path)
upwards, as in the paper's figures.
"""

from __future__ import annotations

import math

import numpy as np

from rov_envs.sim.config import EnvConfig
from rov_envs.sim.tasks import PATH_SINE

WIDTH = 640
MARGIN_M = 10.0
BG = (225, 236, 245)
CORRIDOR = (190, 200, 210)
PATH = (30, 60, 170)
OBSTACLE = (200, 40, 40)
MARGIN = (240, 170, 170)
SONAR = (60, 170, 90)
TRAJ = (20, 20, 20)
VEHICLE = (250, 140, 0)


class _Canvas:
    def __init__(self, x0: float, x1: float, y0: float, y1: float, width: int) -> None:
        self.x0, self.y1 = x0, y1
        self.scale = width / (x1 - x0)
        self.w = width
        self.h = max(16, int(math.ceil((y1 - y0) * self.scale)))
        self.img = np.empty((self.h, self.w, 3), dtype=np.uint8)
        self.img[:] = BG

    def px(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return (np.asarray(x) - self.x0) * self.scale, (self.y1 - np.asarray(y)) * self.scale

    def points(self, x: np.ndarray, y: np.ndarray, color, thick: int = 1) -> None:
        c, r = self.px(x, y)
        c = np.rint(c).astype(np.int64)
        r = np.rint(r).astype(np.int64)
        for dr in range(-(thick // 2), thick - thick // 2):
            for dc in range(-(thick // 2), thick - thick // 2):
                rr, cc = r + dr, c + dc
                ok = (rr >= 0) & (rr < self.h) & (cc >= 0) & (cc < self.w)
                self.img[rr[ok], cc[ok]] = color

    def polyline(self, x: np.ndarray, y: np.ndarray, color, thick: int = 1) -> None:
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        if x.size == 0:
            return
        if x.size == 1:
            self.points(x, y, color, thick)
            return
        seg = np.hypot(np.diff(x), np.diff(y)) * self.scale
        n = np.maximum(1, np.ceil(seg * 1.5).astype(np.int64))
        t = np.concatenate([np.arange(k) / k for k in n])
        idx = np.repeat(np.arange(x.size - 1), n)
        xs = np.append(x[idx] + t * (x[idx + 1] - x[idx]), x[-1])
        ys = np.append(y[idx] + t * (y[idx + 1] - y[idx]), y[-1])
        self.points(xs, ys, color, thick)

    def disc(self, x: float, y: float, radius: float, color, ring: float = 0.0) -> None:
        c, r = self.px(x, y)
        rad = radius * self.scale
        r0, r1 = int(max(0, r - rad - 1)), int(min(self.h, r + rad + 2))
        c0, c1 = int(max(0, c - rad - 1)), int(min(self.w, c + rad + 2))
        if r0 >= r1 or c0 >= c1:
            return
        rr, cc = np.mgrid[r0:r1, c0:c1]
        d2 = (rr - r) ** 2 + (cc - c) ** 2
        mask = d2 <= rad * rad
        if ring > 0.0:
            mask &= d2 >= (rad - ring * self.scale) ** 2
        self.img[r0:r1, c0:c1][mask] = color


def path_points(config: EnvConfig, n: int = 600) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) samples of the task's path from the start to the target."""
    x = np.linspace(0.0, config.length, n)
    if config.task.path_kind == PATH_SINE:
        return x, config.amplitude * np.sin(2.0 * math.pi * x / config.wavelength)
    return x, np.zeros_like(x)


def render_topdown(
    config: EnvConfig,
    obstacles: np.ndarray,
    trajectory: np.ndarray,
    state: np.ndarray,
    sonar: np.ndarray | None,
    width: int = WIDTH,
) -> np.ndarray:
    """An (H, width, 3) uint8 picture of the episode so far (see the module docstring)."""
    px, py = path_points(config)
    d_L = config.d_L
    ys = [py.min() - d_L, py.max() + d_L, state[1]]
    if trajectory.size:
        ys += [trajectory[:, 1].min(), trajectory[:, 1].max()]
    xs = [0.0, config.length, state[0]]
    if trajectory.size:
        xs += [trajectory[:, 0].min(), trajectory[:, 0].max()]
    cv = _Canvas(min(xs) - MARGIN_M, max(xs) + MARGIN_M, min(ys) - 3, max(ys) + 3, width)
    # corridor |g| = d_L (offset along the path normal)
    slope = np.gradient(py, px)
    norm = np.hypot(1.0, slope)
    for side in (-1.0, 1.0):
        cv.polyline(px - side * d_L * slope / norm, py + side * d_L / norm, CORRIDOR)
    cv.polyline(px, py, PATH, thick=2)
    for ox, oy, orad in obstacles:
        cv.disc(ox, oy, orad + 2.0, MARGIN, ring=0.35)
        cv.disc(ox, oy, orad, OBSTACLE)
    x, y, psi = float(state[0]), float(state[1]), float(state[5])
    if sonar is not None and sonar.size:
        q = sonar.size
        rmax = config.sonar_range
        span = config.sonar_span
        for j in range(q + 1):
            a = psi - 0.5 * span + j * span / q
            ray_x = np.array([x, x + rmax * math.cos(a)])
            cv.polyline(ray_x, np.array([y, y + rmax * math.sin(a)]), SONAR)
        for j in range(q):
            if sonar[j] < rmax:
                a = psi - 0.5 * span + (j + 0.5) * span / q
                cv.disc(x + sonar[j] * math.cos(a), y + sonar[j] * math.sin(a), 0.8, SONAR)
    if trajectory.size:
        cv.polyline(trajectory[:, 0], trajectory[:, 1], TRAJ, thick=2)
    cv.disc(x, y, 1.2, VEHICLE)
    nose_x = np.array([x, x + 4 * math.cos(psi)])
    cv.polyline(nose_x, np.array([y, y + 4 * math.sin(psi)]), VEHICLE, 2)
    return cv.img
