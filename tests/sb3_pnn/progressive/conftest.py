"""Small prior checkpoints for the progressive tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from progressive_helpers import PATH, ToyRovEnv
from stable_baselines3 import DQN

from sb3_pnn import DiscreteSAC


@pytest.fixture(scope="session")
def priors(tmp_path_factory) -> dict[str, Path]:
    """pf_dqn: DQN on {"path"}; pf_dsac: DiscreteSAC on {"path"}; oa_dsac: DiscreteSAC on
    {"path", "sonar"}; box_dqn: DQN on a Box(2) observation (= the "path" space)."""
    d = tmp_path_factory.mktemp("priors")
    out = {}
    DQN(
        "MultiInputPolicy", ToyRovEnv(("path",)), policy_kwargs=dict(net_arch=[16, 12]), seed=1
    ).save(d / "pf_dqn.zip")
    out["pf_dqn"] = d / "pf_dqn.zip"
    DiscreteSAC(
        "MultiInputPolicy", ToyRovEnv(("path",)), policy_kwargs=dict(net_arch=[16, 16]), seed=2
    ).save(d / "pf_dsac.zip")
    out["pf_dsac"] = d / "pf_dsac.zip"
    DiscreteSAC("MultiInputPolicy", ToyRovEnv(), policy_kwargs=dict(net_arch=[8, 8]), seed=3).save(
        d / "oa_dsac.zip"
    )
    out["oa_dsac"] = d / "oa_dsac.zip"

    class BoxEnv(ToyRovEnv):
        def __init__(self):
            super().__init__(("path",))
            self.observation_space = PATH

    DQN("MlpPolicy", BoxEnv(), policy_kwargs=dict(net_arch=[10]), seed=4).save(d / "box_dqn.zip")
    out["box_dqn"] = d / "box_dqn.zip"
    return out
