"""Numbers as a person reads them: a check of a finished run's Markdown pages for values written
as Python wrote them (a list's brackets, an array's repr, a float's full precision)."""

from __future__ import annotations

import re
from pathlib import Path

# a decimal number standing alone (not in a name such as CSF-32-100, a version or a date)
NUMBER = re.compile(r"(?<![\w.,])-?\d+\.\d+(?![\w.])")
# what only a program writes: a list of numbers, a numpy scalar, a NaN or an infinity
RAW = re.compile(r"\[-?\d[\d.eE+-]*, |np\.float|array\(|\bnan\b|\binf\b", re.IGNORECASE)


def significant_digits(number: str) -> int:
    """The significant digits a decimal number is written with: ``167.60`` has 5."""
    return len(number.lstrip("-").replace(".", "").lstrip("0"))


def raw_values(page: Path, most: int = 4) -> list[str]:
    """Each prose line of ``page`` (not a table row, not a code span) with a decimal number of
    more than ``most`` significant digits or a value written as Python writes it, with its
    line number."""
    found = []
    for n, line in enumerate(page.read_text().splitlines(), start=1):
        if line.startswith("|") or line.startswith("    "):
            continue
        prose = re.sub(r"`[^`]*`", "", line)
        long = [x for x in NUMBER.findall(prose) if significant_digits(x) > most]
        if long or RAW.search(prose):
            found.append(f"{page.name}:{n}: {', '.join(long) or RAW.search(prose).group()}")
    return found


def assert_plain_numbers(results: Path) -> None:
    """Every Markdown page under ``results`` writes its numbers for a person."""
    pages = sorted(results.rglob("*.md"))
    assert pages, results
    found = [hit for page in pages for hit in raw_values(page)]
    assert not found, "\n".join(found)
