"""Actions given as lambdas (the documented `Actions(pre=[lambda ...], post=[lambda ...])`) share a name and all run."""

from __future__ import annotations

import pytest

from orc_rpl.errors import UsageError
from orc_rpl.motion import Actions, CartesianMotion, MotionLayer, Params

from .motion_helpers import pose_here

pytestmark = pytest.mark.sim


def test_lambdas_in_one_action_set_all_run(kinematic: MotionLayer) -> None:
    seen: list[str] = []
    acts = Actions(pre=[lambda d, slot: seen.append("pre 1"), lambda d, slot: seen.append("pre 2")],
                   post=[lambda d, slot: seen.append("post")])
    handle = kinematic.move(CartesianMotion(pose_here(kinematic, 0.0, 0.05, 0.0)), Params(), acts)
    kinematic.wait(handle)
    assert seen == ["pre 1", "pre 2", "post"]
    assert [e.name for stage in ("pre", "post") for e in acts.stage(stage)] == ["<lambda>", "<lambda>_2", "<lambda>_3"]


def test_an_explicit_name_given_twice_is_still_refused() -> None:
    acts = Actions()
    acts.add("pre", lambda d, slot: None, name="close")
    with pytest.raises(UsageError, match="an action named 'close' is already in this action set"):
        acts.add("post", lambda d, slot: None, name="close")
