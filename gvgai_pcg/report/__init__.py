"""The results report: the study's Table 1 per game (Markdown, CSV, HTML) and its Figure 2
(pooled training curves with the difficulty), built from run directories."""

from gvgai_pcg.report.build import Report, build_report
from gvgai_pcg.report.table import Cell, GameTable, Row, RunResults, build_table

__all__ = ["Cell", "GameTable", "Report", "Row", "RunResults", "build_report", "build_table"]
