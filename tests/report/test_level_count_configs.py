"""A level-count sweep is one training config: sweeps that differ in another key are two curves."""

from __future__ import annotations

from types import SimpleNamespace

from gvgai_pcg.report.generalisation import level_count_curves
from gvgai_pcg.report.table import RunResults


def run(count: int, lr: float, seed: int):
    regimen = {"name": "pcg", "difficulty": 1.0, "num_levels": count}
    config = {"regimen": regimen, "algo": {"lr": lr}, "seed": seed}
    info = SimpleNamespace(game="zelda", regimen=regimen, frames=1000, config=config)
    records = [SimpleNamespace(test_set="pcg1", scores=[float(count)])]
    return info, RunResults("PCG 1", 1000, (), records, f"{count}-{lr}-{seed}", config)


def test_sweeps_of_two_learning_rates_are_two_curves_named_by_the_rate():
    runs = [run(count, lr, seed) for count in (1, 2) for lr in (7e-4, 1e-3) for seed in (0, 1)]
    curves = level_count_curves(runs)
    assert sorted(curve.label for curve in curves) == [
        "PCG 1 (1k; algo.lr=0.0007)",
        "PCG 1 (1k; algo.lr=0.001)",
    ]
    assert all(point.runs == 2 for curve in curves for point in curve.points)
    one = level_count_curves([r for r in runs if r[0].config["algo"]["lr"] == 7e-4])
    assert [curve.label for curve in one] == ["PCG 1 (1k)"]
