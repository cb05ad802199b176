"""Shared helpers for the rov_envs task-layer tests."""

from __future__ import annotations

import gymnasium as gym
import pytest

import rov_envs


@pytest.fixture(params=rov_envs.ENV_IDS)
def env_id(request: pytest.FixtureRequest) -> str:
    return request.param


def make(env_id: str, **kwargs) -> gym.Env:
    return gym.make(env_id, **kwargs)
