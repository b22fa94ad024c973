"""The application layer's value types that features return to programs (the executive prints and indexes them)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True, slots=True)
class Record:
    """A value with named fields (`GrindingPars(tolerance = 0.2mm)`, an identification recording)."""

    type_name: str
    fields: tuple[tuple[str, Any], ...]

    def get(self, name: str) -> Any:
        for key, value in self.fields:
            if key == name:
                return value
        raise KeyError(name)

    def replace(self, name: str, value: Any) -> Record:
        """The same record with one field changed (or added)."""
        items = [(k, value if k == name else v) for k, v in self.fields]
        if all(k != name for k, _ in self.fields):
            items.append((name, value))
        return Record(self.type_name, tuple(items))
