"""The stiffness check's column with its unit, as Stage 2 adds it to the dataset
(:mod:`qsm.dataset.columns` collects every domain's)."""

from __future__ import annotations

#: The stiffness column Stage 2 adds (:class:`qsm.embodiment.stiffness.sag_check.SagCheck`).
STIFFNESS_COLUMNS: dict[str, str] = {
    "tool_sag_mm": "largest sag of the tool under the payload's weight at the task points: solid "
    "links of the configured section, rigid drives (mm; g15 compares it with task.tolerance_mm)",
}
