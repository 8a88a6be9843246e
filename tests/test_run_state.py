"""What a run leaves a person (qsm.workflow.run_state): one run at a time in a directory, and a
failed run's marks on the last good run's results where the config changed."""

import json
import os
import subprocess
import sys
import time

import pytest

from qsm.workflow import run_state as rs

LAST_GOOD = {"task": {"payload_kg": 5.0, "points": [[-0.6, 0.1], [-0.5, 0.1]]}, "seed": 1}
LOG = """Error in rule cycle_time:
    jobid: 3
Error in rule cycle_time:
Error in rule topology_optimize:
"""

HTML = "<html>\n<head><title>summary</title></head>\n<body>\n<h1>summary</h1>\n</body>\n</html>\n"


def _results(tmp_path):
    results = tmp_path / "results"
    (results / "realization").mkdir(parents=True)
    (results / "summary.md").write_text("# summary\n\n**Ready to build**\n")
    (results / "datasheet.md").write_text("# datasheet\n")
    (results / "html").mkdir()
    (results / "html/summary.html").write_text(HTML)
    os.utime(results / "summary.md", ns=(1_000_000_000, 1_000_000_000))
    rs.clear_marks(results, LAST_GOOD, 0.0)  # the last good run
    return results


def test_the_changed_keys_are_named_dotted():
    now = {"task": {"payload_kg": 0.5, "points": [[-0.6, 0.1], [-0.5, 0.1]]}, "extra": {"a": 1}}
    assert rs.changed_keys(LAST_GOOD, now) == ["extra.a", "seed", "task.payload_kg"]
    assert rs.changed_keys(LAST_GOOD, LAST_GOOD) == []


def test_the_failed_rules_come_from_snakemakes_log_once_each():
    assert rs.failed_rules(LOG) == ["cycle_time", "topology_optimize"]
    assert rs.failed_rules("Nothing to be done") == []


def test_a_failure_after_a_config_change_marks_the_results_and_a_success_clears_them(tmp_path):
    results = _results(tmp_path)
    log = tmp_path / "run.log"
    log.write_text(LOG)
    mtime = (results / "summary.md").stat().st_mtime_ns
    changed = LAST_GOOD | {"seed": 2}
    failed = rs.failure(results, changed, [str(log)])
    assert failed.changed == ("seed",)
    rs.mark_not_current(results, failed)
    summary = (results / "summary.md").read_text()
    assert summary.startswith(rs.BANNER) and "cycle_time, topology_optimize" in summary
    assert summary.endswith("# summary\n\n**Ready to build**\n")
    assert (results / "summary.md").stat().st_mtime_ns == mtime  # nothing reruns for it
    assert "(seed)" in (results / "realization" / rs.MARKER).read_text()
    assert "the config changed since the last good run (seed)" in failed.message(results)
    page = (results / "html/summary.html").read_text()  # the HTML copy says so too
    assert page.startswith("<html>\n<head><title>summary</title></head>\n<body>\n<p class=")
    assert "<strong>NOT CURRENT</strong>: a later run failed in cycle_time" in page
    rs.mark_not_current(results, failed)  # twice: one banner
    assert (results / "summary.md").read_text().count(rs.BANNER) == 1
    assert (results / "html/summary.html").read_text() == page
    rs.clear_marks(results, changed, time.time() + 60)  # a run of one rule: kept
    assert (results / "summary.md").read_text().startswith(rs.BANNER)
    rs.clear_marks(results, changed, 0.0)  # a run that wrote the summary
    assert (results / "summary.md").read_text() == "# summary\n\n**Ready to build**\n"
    assert (results / "html/summary.html").read_text() == HTML
    assert not (results / rs.MARKER).exists()
    assert not (results / "realization" / rs.MARKER).exists()
    assert json.loads((results / rs.GOOD_CONFIG).read_text()) == changed


def test_a_run_back_on_the_last_good_config_clears_the_marks_without_rerunning(tmp_path):
    """A failure after a change marks the results; a run on the last good config again, with
    nothing to do (it writes no summary), finds them current and takes the marks away."""
    results = _results(tmp_path)
    rs.mark_not_current(results, rs.failure(results, LAST_GOOD | {"seed": 2}, []))
    assert (results / "summary.md").read_text().startswith(rs.BANNER)
    rs.clear_marks(results, LAST_GOOD | {"seed": 2}, time.time() + 60)  # the changed one: kept
    assert (results / "realization" / rs.MARKER).exists()
    rs.clear_marks(results, LAST_GOOD, time.time() + 60)
    assert (results / "summary.md").read_text() == "# summary\n\n**Ready to build**\n"
    assert not (results / "realization" / rs.MARKER).exists()
    assert json.loads((results / rs.GOOD_CONFIG).read_text()) == LAST_GOOD


def test_a_failure_with_the_same_config_leaves_the_results_unmarked(tmp_path):
    results = _results(tmp_path)
    failed = rs.failure(results, LAST_GOOD, [])
    rs.mark_not_current(results, failed)
    assert not (results / "summary.md").read_text().startswith(rs.BANNER)
    assert not (results / rs.MARKER).exists()
    message = failed.message(results)
    assert "the config is the last good run's" in message and "still describe it" in message


def test_without_a_record_of_the_last_good_config_the_results_are_marked(tmp_path):
    results = _results(tmp_path)
    (results / rs.GOOD_CONFIG).unlink()
    failed = rs.failure(results, LAST_GOOD, [])
    assert failed.changed is None
    rs.mark_not_current(results, failed)
    assert (results / "datasheet.md").read_text().startswith(rs.BANNER)
    assert "no record of the last good run's config" in failed.message(results)


def _design_files(results):
    """A summary that names the bill of materials and the parts, both there, before the last
    good run's record."""
    (results / "summary.md").write_text(
        "# summary\n\n**Ready to build**\n\n- bill of materials: results/realization/bom.csv; "
        "parts to print: results/realization/stl/*.stl; the kit: results/realization/kit/.\n"
    )
    (results / "realization/stl").mkdir()
    (results / "realization/kit").mkdir()
    for name in ("bom.csv", "choice.json", "stl/lower_arm.stl"):
        (results / "realization" / name).write_text("x")
    (results / "logs").mkdir()
    rs.clear_marks(results, LAST_GOOD, 0.0)
    later = (results / rs.GOOD_CONFIG).stat().st_mtime_ns + 10**9
    return later


def test_a_failed_run_names_what_it_rewrote_and_what_is_gone(tmp_path):
    """Jobs of the failed run rewrote choice.json (and a log) under the new config, and
    Snakemake removed the failed job's bom.csv: the message, the banner and the marker name
    both; a run back on the last good config keeps the marks while they hold."""
    results = _results(tmp_path)
    later = _design_files(results)
    os.utime(results / "realization/choice.json", ns=(later, later))
    (results / "logs/x.log").write_text("log")  # a log: not a result
    os.utime(results / "logs/x.log", ns=(later, later))
    (results / "realization/bom.csv").unlink()
    failed = rs.failure(results, LAST_GOOD | {"seed": 2}, [])
    assert (failed.rewritten, failed.missing) == (
        ("realization/choice.json",),
        ("realization/bom.csv",),
    )
    message = failed.message(results)
    assert "the failed run rewrote realization/choice.json for its own config" in message
    assert "realization/bom.csv, which the summary names, is gone" in message
    rs.mark_not_current(results, failed)
    banner = (results / "summary.md").read_text().split("\n\n", 1)[0]
    assert "rewrote realization/choice.json" in banner and "bom.csv, which" in banner
    rs.clear_marks(results, LAST_GOOD, time.time() + 60)  # the last good config, one rule run
    assert (results / "realization" / rs.MARKER).exists()  # its results are still a mix
    same = rs.failure(results, LAST_GOOD, [])  # a failure with the last good config
    assert "but for realization/bom.csv, which the summary names, is gone" in same.message(results)


def test_the_run_lock_refuses_a_second_process_and_frees_with_the_first(tmp_path):
    lock = tmp_path / ".snakemake" / "qsm_run.lock"
    holder = subprocess.Popen(
        [sys.executable, "-c",
         f"from qsm.workflow.run_state import hold_run_lock; import time\n"
         f"hold_run_lock({str(lock)!r}); print('held', flush=True); time.sleep(30)"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert holder.stdout.readline().strip() == "held"
        with pytest.raises(rs.RunLocked, match=f"another qsm run .*process {holder.pid}"):
            rs.hold_run_lock(lock)
        assert not rs.holds_run_lock()
    finally:
        holder.kill()
        holder.wait()
    deadline = time.monotonic() + 10
    while True:  # the system frees the lock with the process
        try:
            rs.hold_run_lock(lock)
            break
        except rs.RunLocked:
            assert time.monotonic() < deadline
            time.sleep(0.1)
    assert rs.holds_run_lock()
    rs._HELD.pop().close()


def test_a_first_run_that_fails_marks_nothing_and_says_there_is_nothing_earlier(tmp_path):
    results = tmp_path / "results"
    (results / "realization").mkdir(parents=True)
    failed = rs.failure(results, LAST_GOOD, [])
    assert not failed.earlier
    rs.mark_not_current(results, failed)
    assert not (results / rs.MARKER).exists()
    assert "no earlier run left results" in failed.message(results)
