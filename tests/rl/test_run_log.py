"""The run log is cut back to a checkpoint, also after a kill in the middle of a write."""

import csv

from gvgai_pcg.rundir.run_log import COLUMNS, cut_log, cut_torchrl_csv, read_log


def _write_rows(path, frames_and_episodes) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=COLUMNS)
        writer.writeheader()
        for frames, episodes in frames_and_episodes:
            writer.writerow({**dict.fromkeys(COLUMNS, 0.5), "frames": frames, "episodes": episodes})


def test_cut_log_keeps_the_rows_up_to_the_checkpoint(tmp_path):
    path = tmp_path / "log.csv"
    _write_rows(path, [(320, 12), (640, 24), (960, 36)])
    assert cut_log(path, 640) == 24
    assert [row["frames"] for row in read_log(path)] == [320, 640]


def test_a_last_row_cut_short_by_a_kill_is_dropped(tmp_path):
    path = tmp_path / "log.csv"
    _write_rows(path, [(320, 12), (640, 24)])
    with open(path, "a") as handle:
        handle.write("960,36,0.5,0")  # the kill came in the middle of this row
    assert [row["frames"] for row in read_log(path)] == [320, 640]
    assert cut_log(path, 10_000) == 24
    assert [row["frames"] for row in read_log(path)] == [320, 640]


def test_torchrl_csv_files_are_cut_back_and_lose_a_line_cut_short(tmp_path):
    (tmp_path / "mean_score.csv").write_text("320,0.5\n640,0.25\n960,0.125\n1280,0.0625\n")
    cut_torchrl_csv(tmp_path, 960)
    assert (tmp_path / "mean_score.csv").read_text() == "320,0.5\n640,0.25\n960,0.125\n"
    (tmp_path / "entropy.csv").write_text("320,1.5\n640,1.2")  # killed while writing 640,1.25
    cut_torchrl_csv(tmp_path, 960)
    assert (tmp_path / "entropy.csv").read_text() == "320,1.5\n"
