"""The results tables written out: Markdown (for docs), CSV (one line per cell, for analysis) and
a self-contained HTML page (tables and the training-curve figures)."""

from __future__ import annotations

import csv
import html
import io
from collections.abc import Sequence
from pathlib import Path

from gvgai_pcg.report.table import COLUMN_LABELS, Cell, GameTable
from gvgai_pcg.rundir.atomic_files import atomic_write_text

CSV_COLUMNS = (
    "game",
    "row",
    "kind",
    "regimen",
    "frames",
    "runs",
    "test_set",
    "mean",
    "std",
    "training",
    "best",
    "seed_means",
    "ci95_low",
    "ci95_high",
)
LEGEND = (
    "Mean over runs (seeds) of each run's mean score, ± the standard deviation across runs (population "
    "SD, as the study computed it; not a confidence interval: the claims give 95 % t intervals, and "
    "`results.csv` each run's mean and the 95 % t interval of every cell); no ± for a single run. "
    "† = a test set the row trained on (Train: each run's own training levels); "
    "**bold** = best held-out score of the column (none where all tie)."
)


def figure_title(game: str, figure: Path) -> str:
    if figure.stem.startswith("generalisation-"):
        return f"{game}: score against the number of training levels"
    return f"{game} training curves"


def cell_text(cell: Cell | None) -> str:
    if cell is None:
        return "–"
    text = f"{cell.mean:.2f}" if cell.std is None else f"{cell.mean:.2f} ± {cell.std:.2f}"
    return text + (" †" if cell.training else "")


def markdown_table(table: GameTable) -> str:
    header = ["", *(COLUMN_LABELS.get(c, c) for c in table.columns)]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in table.rows:
        cells = []
        for column in table.columns:
            cell = row.cells.get(column)
            text = cell_text(cell)
            cells.append(f"**{text}**" if cell is not None and cell.best else text)
        lines.append(f"| {row.name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def markdown_report(tables: Sequence[GameTable], figures: dict[str, list[Path]] | None = None) -> str:
    parts = ["# Results", "", LEGEND, ""]
    for table in tables:
        parts += [f"## {table.game}", "", markdown_table(table), ""]
        for figure in (figures or {}).get(table.game, []):
            if figure.suffix == ".png":
                parts += [f"![{figure_title(table.game, figure)}]({figure.name})", ""]
    return "\n".join(parts)


def write_csv(tables: Sequence[GameTable], path: Path) -> Path:
    with io.StringIO() as handle:  # written whole: a kill leaves the old file
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(CSV_COLUMNS)
        for table in tables:
            for row in table.rows:
                for column in table.columns:
                    cell = row.cells.get(column)
                    if cell is None:
                        continue
                    writer.writerow(
                        (
                            table.game,
                            row.name,
                            row.kind,
                            row.regimen,
                            row.frames,
                            cell.runs,
                            column,
                            f"{cell.mean:.6g}",
                            "" if cell.std is None else f"{cell.std:.6g}",
                            int(cell.training),
                            int(cell.best),
                            ";".join(f"{v:.6g}" for v in cell.seed_means),
                            "" if cell.ci95 is None else f"{cell.ci95[0]:.6g}",
                            "" if cell.ci95 is None else f"{cell.ci95[1]:.6g}",
                        )
                    )
        atomic_write_text(path, handle.getvalue())
    return path


def html_table(table: GameTable) -> str:
    head = "".join(f"<th>{html.escape(COLUMN_LABELS.get(c, c))}</th>" for c in table.columns)
    body = []
    for row in table.rows:
        tds = []
        for column in table.columns:
            cell = row.cells.get(column)
            classes = (
                [] if cell is None else [n for n, on in (("train", cell.training), ("best", cell.best)) if on]
            )
            text = html.escape(cell_text(cell))
            text = f"<strong>{text}</strong>" if cell is not None and cell.best else text
            tds.append(f'<td class="{" ".join(classes)}">{text}</td>')
        body.append(f"<tr><th>{html.escape(row.name)}</th>{''.join(tds)}</tr>")
    return f"<table><thead><tr><th></th>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def html_report(tables: Sequence[GameTable], figures: dict[str, list[Path]] | None = None) -> str:
    style = (
        "body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin-bottom:1em}"
        "td,th{border:1px solid #ccc;padding:4px 8px;text-align:right}td.train{background:#e8e8e8}"
    )
    parts = [f"<!doctype html><html><head><meta charset='utf-8'><title>Results</title><style>{style}</style>"]
    parts.append(
        f"</head><body><h1>Results</h1><p>{html.escape(LEGEND).replace('**bold**', '<b>bold</b>')}</p>"
    )
    for table in tables:
        parts.append(f"<h2>{html.escape(table.game)}</h2>{html_table(table)}")
        for figure in (figures or {}).get(table.game, []):
            if figure.suffix == ".svg":
                title = html.escape(figure_title(table.game, figure))
                parts.append(f'<p><img src="{html.escape(figure.name)}" alt="{title}"></p>')
    parts.append("</body></html>")
    return "\n".join(parts)
