"""What a run leaves a person: one run at a time in a working directory, and, when a run fails,
the last good run's results marked as not current where the config has changed since.

A successful run records its config (``results/.last_good_config.json``). A failed run compares
the config it was given with that record: where keys changed, the last good run's summary and
datasheet get a NOT CURRENT banner (their modification times kept, so Snakemake reruns nothing
for it) and ``NOT_CURRENT.md`` is written beside the design files, naming the failed rule and
the keys; where nothing changed, the results still describe the config and stay as they are.
The next successful run that writes the summary takes the marks away.
"""

from __future__ import annotations

import fcntl
import html
import json
import os
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

#: The record of the last good run's config, under the results folder.
GOOD_CONFIG = ".last_good_config.json"
#: The marker written beside the design files of a run that is no longer current.
MARKER = "NOT_CURRENT.md"
#: The first line of the banner on a summary or datasheet that is no longer current.
BANNER = "> **NOT CURRENT**"
#: The Markdown files a banner is put on, under the results folder.
BANNERED = ("summary.md", "datasheet.md")
#: The folders of design files a marker is written into, under the results folder.
MARKED = (".", "realization")
#: The HTML copies of the bannered pages (rule markdown_pages), under the results folder.
BANNERED_HTML = ("html/summary.html", "html/datasheet.html")
#: The banner's element in an HTML copy, put first in its body.
HTML_BANNER = '<p class="not-current"><strong>NOT CURRENT</strong>: {}</p>\n'
#: Folders under the results that hold the jobs' logs and timings, not results.
NOT_RESULTS = ("logs", "benchmarks")
#: How many file names a message lists before "and N more".
LISTED = 4

_HELD: list[IO[str]] = []


class RunLocked(RuntimeError):
    """Another run works in this directory."""


def hold_run_lock(path: str | Path) -> None:
    """Take the directory's run lock at ``path`` for the rest of this process (an exclusive
    ``flock``, released by the system when the process ends, however it ends); RunLocked,
    naming the holder's process, when another run holds it."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    handle = open(path, "a+")  # held open until the process ends
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        handle.seek(0)
        holder = handle.read().strip() or "unknown"
        handle.close()
        raise RunLocked(
            f"another qsm run is working in this directory (process {holder}); wait for it "
            f"to end, or stop it, before starting one here ({path})"
        ) from None
    handle.truncate(0)
    handle.write(str(os.getpid()))
    handle.flush()
    _HELD.append(handle)


def holds_run_lock() -> bool:
    """Whether this process holds the run lock."""
    return bool(_HELD)


def flat(config: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """``config`` as dotted keys to JSON values (lists kept whole)."""
    out: dict[str, Any] = {}
    for key, value in config.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and value:
            out |= flat(value, name + ".")
        else:
            out[name] = value
    return out


def changed_keys(before: Mapping[str, Any], now: Mapping[str, Any]) -> list[str]:
    """The dotted keys whose values differ between two configs, sorted."""
    a, b = flat(before), flat(json.loads(json.dumps(now, default=str)))
    return sorted(k for k in a.keys() | b.keys() if a.get(k) != b.get(k))


def failed_rules(log_text: str) -> list[str]:
    """The rules Snakemake's log says failed, in order, once each."""
    return list(dict.fromkeys(re.findall(r"Error in rule (\w+):", log_text)))


@dataclass(frozen=True)
class Failure:
    """A failed run: the ``rules`` that failed, the config ``changed`` keys since the last
    good run (None: no record of its config), whether an ``earlier`` run left results (a
    summary or a recorded config), and since the last good run the result files ``rewritten``
    (by the failed run's jobs that succeeded) and the ones the summary names that are
    ``missing`` (Snakemake removes a failed job's outputs), relative to the results folder."""

    rules: tuple[str, ...]
    changed: tuple[str, ...] | None
    earlier: bool = True
    rewritten: tuple[str, ...] = ()
    missing: tuple[str, ...] = ()

    def message(self, results: Path) -> str:
        """What the console says."""
        where = ", ".join(self.rules) or "a rule the log does not name"
        if not self.earlier:
            return f"qsm: the run failed in {where}; no earlier run left results in {results}"
        if self.changed == ():
            return (
                f"qsm: the run failed in {where}; the config is the last good run's, so its "
                f"results in {results} still describe it and stay as they are"
                + (f", but for {_gone_text(self.missing)}" if self.missing else "")
            )
        why = (
            "no record of the last good run's config was found"
            if self.changed is None
            else "the config changed since the last good run (" + ", ".join(self.changed[:8])
            + (", ..." if len(self.changed) > 8 else "") + ")"
        )  # fmt: skip
        return (
            f"qsm: the run failed in {where}, and {why}: the summary and datasheet in {results} "
            f"are the last good run's, not this config's, and are marked NOT CURRENT "
            f"({results / MARKER}); {self._mixed()}; a successful run replaces them"
        )

    def banner(self) -> str:
        """The Markdown banner on a summary or datasheet."""
        return f"{BANNER}: {self._why()}\n\n"

    def html_banner(self) -> str:
        """The banner on an HTML copy of a summary or datasheet."""
        return HTML_BANNER.format(html.escape(self._why()))

    def _why(self) -> str:
        """Why a page is not current: where the later run failed and the keys that changed."""
        where = ", ".join(self.rules) or "a rule"
        keys = "an unknown config" if self.changed is None else ", ".join(self.changed)
        return (
            f"a later run failed in {where} after the config changed ({keys}); this is the last "
            f"good run's, for its own config; {self._mixed()}."
        )

    def _mixed(self) -> str:
        """Which result files are no longer the last good run's: rewritten or gone."""
        parts = []
        if self.rewritten:
            parts.append(f"the failed run rewrote {_some(self.rewritten)} for its own config")
        if self.missing:
            parts.append(_gone_text(self.missing))
        return "; ".join(parts) or "no result file was rewritten or removed since"


def _some(names: tuple[str, ...]) -> str:
    """The first :data:`LISTED` of ``names``, and how many more."""
    more = len(names) - LISTED
    return ", ".join(names[:LISTED]) + (f" and {more} more" if more > 0 else "")


def _gone_text(missing: tuple[str, ...]) -> str:
    return f"{_some(missing)}, which the summary names, {'is' if len(missing) == 1 else 'are'} gone"


def failure(results: Path, config: Mapping[str, Any], logs: Iterable[str]) -> Failure:
    """The failed run's :class:`Failure`, from Snakemake's ``logs`` and the last good config."""
    text = "".join(Path(p).read_text(errors="replace") for p in logs if Path(p).exists())
    record = results / GOOD_CONFIG
    changed = (
        tuple(changed_keys(json.loads(record.read_text()), config)) if record.exists() else None
    )
    earlier = record.exists() or (results / BANNERED[0]).exists()
    return Failure(tuple(failed_rules(text)), changed, earlier, *departures(results))


def departures(results: Path) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Since the last good run (its recorded config's time): the result files written later
    (:func:`_written_since`), and the files the summary names that are gone; each relative to
    ``results``, sorted."""
    record, summary = results / GOOD_CONFIG, results / BANNERED[0]
    if not record.exists() or not summary.exists():
        return (), ()
    named = re.findall(rf"{re.escape(results.name)}/[\w./*-]*\w", summary.read_text())
    missing = {n.split("/", 1)[1] for n in named if not any(results.parent.glob(n))}
    return _written_since(results, record.stat().st_mtime_ns), tuple(sorted(missing))


def _written_since(results: Path, since_ns: int) -> tuple[str, ...]:
    """The result files under ``results`` written after ``since_ns`` (not the jobs' logs and
    timings, nor the marks), the design files first."""
    names = [
        str(p.relative_to(results))
        for p in results.rglob("*")
        if p.is_file() and p.stat().st_mtime_ns > since_ns and p.name not in (GOOD_CONFIG, MARKER)
    ]
    kept = [n for n in names if n.split("/", 1)[0] not in NOT_RESULTS]
    return tuple(sorted(kept, key=lambda name: (not name.startswith("realization/"), name)))


def mark_not_current(results: Path, failed: Failure) -> None:
    """Banner the last good run's summary and datasheet and write the marker beside its design
    files (none where the config did not change), their modification times kept."""
    if failed.changed == () or not failed.earlier:
        return
    for name in BANNERED:
        path = results / name
        if path.exists() and not path.read_text().startswith(BANNER):
            _rewrite(path, failed.banner() + path.read_text())
    _banner_html(results, failed.html_banner())
    for folder in MARKED:
        if (results / folder).is_dir():
            (results / folder / MARKER).write_text(failed.banner())


def clear_marks(results: Path, config: Mapping[str, Any], started: float) -> None:
    """After a successful run that wrote the summary (at or after ``started``, seconds since
    the epoch), or one whose config is the last good run's again with no result file written
    or gone since (:func:`departures`: the results describe it): no banner, no marker, and the
    config recorded as the last good. A run of one rule leaves the marks."""
    summary, record = results / BANNERED[0], results / GOOD_CONFIG
    wrote = summary.exists() and summary.stat().st_mtime >= started
    same = record.exists() and not changed_keys(json.loads(record.read_text()), config)
    marked = any((results / folder / MARKER).exists() for folder in MARKED)
    if not (wrote or (same and marked and departures(results) == ((), ()))):
        return
    for name in BANNERED:
        path = results / name
        if path.exists() and path.read_text().startswith(BANNER):
            _rewrite(path, path.read_text().split("\n\n", 1)[1])
    _banner_html(results, None)
    for folder in MARKED:
        (results / folder / MARKER).unlink(missing_ok=True)
    if wrote:
        text = json.dumps(config, default=str, sort_keys=True, allow_nan=False)
        record.write_text(text)


def _banner_html(results: Path, banner: str | None) -> None:
    """Put ``banner`` first in the body of each HTML copy of a bannered page (once), or, with
    None, take it out."""
    for name in BANNERED_HTML:
        path = results / name
        if not path.exists():
            continue
        lines = path.read_text().splitlines(keepends=True)
        kept = [x for x in lines if 'class="not-current"' not in x]
        if banner is not None:
            body = next((i for i, x in enumerate(kept) if x.startswith("<body")), -1)
            kept.insert(body + 1, banner)
        if kept != lines:
            _rewrite(path, "".join(kept))


def _rewrite(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` keeping its modification time."""
    stat = path.stat()
    path.write_text(text)
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns))
