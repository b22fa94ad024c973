"""The verify table: its columns, the process column only when a run reports a process section."""

from __future__ import annotations

import io

from rich.console import Console

from orc_rpl.verify.judge import FAIL, Row
from orc_rpl.verify.table import build_table


def _text(rows: list[Row], have_baseline: bool = True) -> str:
    console = Console(width=250, record=True, file=io.StringIO())
    console.print(build_table(rows, have_baseline))
    return console.export_text()


def test_a_process_section_gets_its_column() -> None:
    plain = Row("a.rpl", "irb2400", "finished", cycle_time_s=1.5, motions=3, clearance_mm=120.0)
    welded = Row("b.rpl", "irb2400", "finished", cycle_time_s=2.0, motions=6, clearance_mm=80.0,
                 process={"welds": [{"good": True}, {"good": False}], "bulges": [], "spatter_mm": 0.25,
                          "faults": [{"exception": "WeldFault", "caught": False}]})
    assert "process" not in _text([plain]).splitlines()[2]
    text = _text([plain, welded])
    assert "process" in text and "welds 2 (1 good), spatter_mm=0.25, faults 1 (1 not caught)" in text


def test_rows_show_retries_collisions_baseline_changes_and_reasons() -> None:
    row = Row("c.rpl", "ur5e", "finished", cycle_time_s=1.1, baseline_cycle_time_s=1.0, change_pct=10.0, motions=2,
              clearance_mm=-3.0, attempts=2, verdict=FAIL, reasons=("collision: robot/link5 to table_top at 1.00 s",))
    text = _text([row])
    assert "finished, retried 1x" in text and "+10.0 %" in text and "-3 mm COLLISION" in text
    assert "FAIL: collision: robot/link5 to table_top at 1.00 s" in text
    nearer = Row("e.rpl", "irb2400", "finished", cycle_time_s=1.0, motions=1, clearance_mm=30.2, clearance_at="e.rpl:7",
                 baseline_clearance_mm=45.0, joint_margin_deg=12.34, margin_joint=4, margin_at="e.rpl:5")
    assert "30 mm @7 (-15)" in _text([nearer]) and "12.3 deg j4 @5" in _text([nearer])
    fresh = Row("d.rpl", "irb2400", "finished", cycle_time_s=1.0, motions=1)
    assert "new" in _text([fresh]) and "new" not in _text([fresh], have_baseline=False)
