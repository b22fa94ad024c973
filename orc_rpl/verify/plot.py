"""The sweep's plot: outcomes against one parameter, a panel each, a line per combination of the others, seeds as a band."""

from __future__ import annotations

import re
from collections import defaultdict
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only, never a window
import matplotlib.pyplot as plt  # noqa: E402

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z/%]*)\s*$")


def numeric(text: str) -> tuple[float, str] | None:
    """`1.5mps` -> (1.5, "mps"); None for a value that is not a number with an optional unit."""
    match = _NUMBER.match(str(text))
    return (float(match.group(1)), match.group(2)) if match else None


def plot_outcomes(records: list[dict[str, Any]], parameter: str, outcomes: list[str], others: list[str], path: Path,
                  title: str) -> int:
    """Plot each of `outcomes` against `parameter`, one panel each, one above the other; seeds of one point are
    averaged with their range as error bars.

    Returns how many points were plotted (runs without an outcome, e.g. failed ones, are left out of its panel).
    """
    figure, panels = plt.subplots(len(outcomes), 1, figsize=(7, 1.0 + 3.5 * len(outcomes)), squeeze=False)
    plotted = sum(_panel(axes, records, parameter, outcome, others) for axes, outcome in zip(panels[:, 0], outcomes))
    panels[0, 0].set_title(title)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return plotted


def _panel(axes: Any, records: list[dict[str, Any]], parameter: str, outcome: str, others: list[str]) -> int:
    series: dict[tuple[Any, ...], dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for record in records:
        value = record.get(outcome)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        label = tuple(record.get(name) for name in others)
        series[label][str(record[parameter])].append(float(value))
    xs_all = sorted({x for points in series.values() for x in points},
                    key=lambda x: (numeric(x) is None, numeric(x)[0] if numeric(x) else 0.0, x))
    is_numeric = all(numeric(x) is not None for x in xs_all)
    unit = next((numeric(x)[1] for x in xs_all if is_numeric and numeric(x)[1]), "")
    plotted = 0
    for label, points in sorted(series.items(), key=lambda item: str(item[0])):
        xs = [x for x in xs_all if x in points]
        position = [numeric(x)[0] if is_numeric else xs_all.index(x) for x in xs]  # type: ignore[index]
        mean = [sum(points[x]) / len(points[x]) for x in xs]
        low = [m - min(points[x]) for m, x in zip(mean, xs)]
        high = [max(points[x]) - m for m, x in zip(mean, xs)]
        name = ", ".join(f"{o}={v}" for o, v in zip(others, label)) or outcome
        axes.errorbar(position, mean, yerr=[low, high], marker="o", capsize=3, label=name)
        plotted += sum(len(points[x]) for x in xs)
    if not is_numeric:
        axes.set_xticks(range(len(xs_all)), xs_all)
    axes.set_xlabel(f"{parameter} ({unit})" if unit else parameter)
    axes.set_ylabel(outcome)
    axes.grid(True, alpha=0.3)
    if len(series) > 1:
        axes.legend(fontsize="small")
    return plotted
