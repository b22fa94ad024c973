"""`orc run --video`: an MP4 of the run at the simulated clock's real-time speed, read back frame by frame."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tests.view.support import ROOT, orc

imageio = pytest.importorskip("imageio.v2", reason="videos are the [view] extra")

from orc_rpl.view.video import FPS, frames_for  # noqa: E402

pytestmark = pytest.mark.sim


def test_video_has_a_frame_per_25th_of_a_simulated_second(tmp_path) -> None:
    video, summary = tmp_path / "run.mp4", tmp_path / "run.json"
    proc = orc("run", str(ROOT / "programs" / "online" / "thesis_4_1_move_via.rpl"), "--video", str(video),
               "--summary-json", str(summary))
    out, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.json", "run.mp4"], "no temporary file is left behind"
    cycle_s = json.loads(summary.read_text())["cycle_time_s"]
    reader = imageio.get_reader(str(video))
    try:
        assert reader.get_meta_data()["fps"] == FPS
        frames = [frame for frame in reader]
    finally:
        reader.close()
    assert len(frames) == frames_for(cycle_s) == int(np.floor(cycle_s * FPS + 1e-6)) + 1
    first, last = frames[0].astype(int), frames[-1].astype(int)
    assert first.shape == (480, 640, 3)
    # the robot moved between the first and the last frame (the caption band aside)
    assert np.abs(first[:-40] - last[:-40]).mean() > 1.0
    # the caption band is dark with light text
    band = last[-30:]
    assert band.mean() < 80 and band.max() > 200


def test_video_refuses_a_file_that_is_not_mp4(tmp_path) -> None:
    proc = orc("run", str(ROOT / "programs" / "online" / "thesis_4_1_move_via.rpl"), "--video", str(tmp_path / "run.avi"))
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 2
    assert "--video: the file must end in .mp4" in err
