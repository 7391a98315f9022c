"""updates.csv: rows from the first update, cut back to the checkpoint on resume."""

from __future__ import annotations

from gvgai_pcg.rundir.update_log import UPDATE_COLUMNS, UpdateLog, cut_updates, read_updates


class Recorder:
    def __init__(self) -> None:
        self.calls: list[tuple[str, float, int]] = []

    def log_scalar(self, name: str, value: float, step: int) -> None:
        self.calls.append((name, value, step))


def _row(frames: int) -> dict[str, float]:
    return {"frames": frames, "updates": frames // 32, "policy_loss": 0.1, "value_loss": 0.2, "entropy": 1.5}


def test_rows_are_written_mirrored_and_cut_back_on_resume(tmp_path):
    recorder = Recorder()
    log = UpdateLog(tmp_path, [recorder], resume_frames=None)
    for frames in (32, 64, 96):
        log.write(_row(frames))
    log.close()
    rows = read_updates(tmp_path / "updates.csv")
    assert [row["frames"] for row in rows] == [32, 64, 96] and set(rows[0]) == set(UPDATE_COLUMNS)
    assert ("update_entropy", 1.5, 64) in recorder.calls
    with open(tmp_path / "updates.csv", "a") as f:
        f.write("128,4,0.1")  # a row cut short by a kill
    log = UpdateLog(tmp_path, [], resume_frames=64)  # the checkpoint was at 64 frames
    log.write(_row(96))
    log.close()
    assert [row["frames"] for row in read_updates(tmp_path / "updates.csv")] == [32, 64, 96]


def test_a_fresh_start_forgets_an_earlier_log(tmp_path):
    (tmp_path / "updates.csv").write_text("frames,updates\n5,1\n")
    UpdateLog(tmp_path, [], resume_frames=None).close()
    assert read_updates(tmp_path / "updates.csv") == []
    cut_updates(tmp_path / "missing.csv", 10)  # nothing to cut: no error
    assert not (tmp_path / "missing.csv").exists()
