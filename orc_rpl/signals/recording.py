"""The signals room's recordings: time series of named signals, saved as NPZ or CSV and plotted to PNG."""

from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from orc_rpl.errors import UsageError

_COLUMN = re.compile(r"^(?P<name>.+)\[(?P<index>\d+)\]$")


@dataclass(frozen=True)
class Recording:
    """Samples of named signals: `time_s` (n,) and each signal (n,) or (n, k); columns 1-based in CSV."""

    time_s: np.ndarray
    signals: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n = self.time_s.shape[0]
        for name, values in self.signals.items():
            if values.shape[0] != n:
                raise UsageError(f"signal {name!r} has {values.shape[0]} samples, time has {n}")

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.signals[name]
        except KeyError:
            raise UsageError(f"no signal {name!r} in the recording; it has {', '.join(self.signals) or 'none'}") from None

    def __len__(self) -> int:
        return int(self.time_s.shape[0])

    @property
    def names(self) -> list[str]:
        """Signal names in recording order."""
        return list(self.signals)

    # -- files ----------------------------------------------------------------

    def to_npz(self, path: str | Path) -> Path:
        """Save as a NumPy archive: `time_s` and one array per signal (names kept in `__names__`)."""
        out = Path(path)
        arrays = {f"s{i}": v for i, v in enumerate(self.signals.values())}
        np.savez(out, time_s=self.time_s, __names__=np.array(self.names, dtype=str), **arrays)
        return out

    @classmethod
    def from_npz(cls, path: str | Path) -> Recording:
        """Read what to_npz wrote."""
        with np.load(Path(path), allow_pickle=False) as archive:
            names = [str(n) for n in archive["__names__"]]
            return cls(archive["time_s"], {name: archive[f"s{i}"] for i, name in enumerate(names)})

    def to_csv(self, path: str | Path) -> Path:
        """Save as CSV: a header `time_s,q[1],...,q[6],...` then one row per sample, full precision."""
        out = Path(path)
        header = ["time_s"]
        blocks = [self.time_s[:, None]]
        for name, values in self.signals.items():
            if values.ndim == 1:
                header.append(name)
                blocks.append(values[:, None])
            else:
                header += [f"{name}[{i + 1}]" for i in range(values.shape[1])]
                blocks.append(values)
        table = np.hstack(blocks) if blocks else np.empty((0, 1))
        with out.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(header)
            writer.writerows([[repr(float(x)) for x in row] for row in table])
        return out

    @classmethod
    def from_csv(cls, path: str | Path) -> Recording:
        """Read what to_csv wrote (`name[i]` columns join back into one array)."""
        with Path(path).open(newline="") as f:
            reader = csv.reader(f)
            header = next(reader)
            rows = np.array([[float(x) for x in row] for row in reader]).reshape(-1, len(header))
        if header[0] != "time_s":
            raise UsageError(f"{path}: not a recording (first column is {header[0]!r}, expected 'time_s')")
        columns: dict[str, list[int]] = {}
        scalar: set[str] = set()
        for j, column in enumerate(header[1:], start=1):
            match = _COLUMN.match(column)
            name = match["name"] if match else column
            if not match:
                scalar.add(name)
            columns.setdefault(name, []).append(j)
        signals = {name: rows[:, js[0]] if name in scalar else rows[:, js] for name, js in columns.items()}
        return cls(rows[:, 0], signals)

    # -- pictures -------------------------------------------------------------

    def plot_png(self, path: str | Path, signals: list[str] | None = None, tcp: str | None = "tcp",
                 width_in: float = 10.0, title: str | None = None, units: dict[str, str] | None = None) -> Path:
        """Plot signals over time (all but the TCP by default) and the TCP path in x-y and x-z, to a PNG;
        `units` gives each signal's unit for its axis label, `title` heads the figure."""
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib import pyplot as plt

        chosen = [n for n in self.names if n != tcp] if signals is None else list(signals)
        for name in chosen:
            self[name]  # unknown names fail here, with the list of known ones
        has_tcp = tcp is not None and tcp in self.signals and self.signals[tcp].ndim == 2 and self.signals[tcp].shape[1] >= 3
        rows = len(chosen) + (1 if has_tcp else 0)
        if rows == 0:
            raise UsageError("nothing to plot: the recording has no signals")
        fig = plt.figure(figsize=(width_in, 2.4 * rows), layout="constrained")
        if title:
            fig.suptitle(title)
        grid = fig.add_gridspec(rows, 2)
        first = None
        for i, name in enumerate(chosen):
            ax = fig.add_subplot(grid[i, :], sharex=first)  # one time axis for every panel
            first = first or ax
            values = self.signals[name]
            if values.ndim == 1:
                ax.plot(self.time_s, values, lw=1.0)
            else:
                for k in range(values.shape[1]):
                    ax.plot(self.time_s, values[:, k], lw=1.0, label=f"[{k + 1}]")
                ax.legend(loc="upper right", fontsize="x-small", ncols=min(values.shape[1], 6))
            unit = (units or {}).get(name)
            ax.set_ylabel(f"{name} ({unit})" if unit else name)
            ax.grid(True, alpha=0.3)
            ax.set_xlabel("time (s)")
        if has_tcp:
            path_m = self.signals[tcp]
            for col, (k, label) in enumerate(((1, "y (m)"), (2, "z (m)"))):
                ax = fig.add_subplot(grid[rows - 1, col])
                ax.plot(path_m[:, 0], path_m[:, k], lw=1.0)
                ax.set_xlabel("x (m)")
                ax.set_ylabel(label)
                ax.set_title(f"{tcp} path, x-{label[0]}", fontsize="small")
                ax.set_aspect("equal", adjustable="datalim")
                ax.grid(True, alpha=0.3)
        out = Path(path)
        fig.savefig(out, dpi=80)
        plt.close(fig)
        return out
