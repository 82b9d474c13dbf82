"""Specifications of the IK prior's training (benchmarks/colorshirt_train_prior.py)."""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType

import numpy as np
import pytest

from bodyplay.body import Skeleton
from bodyplay.trackers.colorshirt.ik import PriorModel, ik_dofs

SK = Skeleton()


@pytest.fixture(scope="module")
def train_prior(script_loader: Callable[..., ModuleType]) -> ModuleType:
    return script_loader("benchmarks/colorshirt_train_prior.py")


def test_prior_model_fit_gives_positive_stds_per_free_dof(train_prior) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(0)
    truth = np.tile(SK.rest_pose(), (50, 1)) + rng.normal(0, 0.05, (50, SK.pose_dim))
    blended = truth + rng.normal(0, 0.2, truth.shape)
    pm = train_prior.fit_prior_model(truth, blended, rng.normal(0, 0.03, 200))
    assert len(pm.blend) == len(ik_dofs())
    assert 0.1 < np.median(pm.blend) < 0.3
    assert np.median(pm.previous) < np.median(pm.blend)
    assert PriorModel.from_dict(pm.to_dict()) == pm
