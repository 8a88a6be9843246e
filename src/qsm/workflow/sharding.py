"""Fixed, contiguous shards of a table, so results do not depend on the shard count."""

from __future__ import annotations


def shard_slice(n_rows: int, n_shards: int, shard: int) -> slice:
    """Rows of shard ``shard`` (0-based) when ``n_rows`` rows are cut into ``n_shards`` parts.

    Parts differ in size by at most one row; concatenating them in order gives all rows once.
    """
    if n_shards < 1:
        raise ValueError(f"the shard count must be at least 1, got {n_shards}")
    if not 0 <= shard < n_shards:
        raise ValueError(f"shard {shard} is outside 0..{n_shards - 1}")
    base, extra = divmod(n_rows, n_shards)
    start = shard * base + min(shard, extra)
    return slice(start, start + base + (shard < extra))


def shard_count(n_rows: int, least: int, rows_per_shard: int) -> int:
    """Shards for ``n_rows`` rows: ``least`` (the jobs to run side by side), or a multiple of it
    where a shard would hold over ``rows_per_shard`` rows (which bounds each job's memory), so
    that the jobs run in full rounds of ``least``."""
    if least < 1 or rows_per_shard < 1:
        raise ValueError(f"need least >= 1 and rows_per_shard >= 1, got {least}, {rows_per_shard}")
    return least * max(1, -(-n_rows // (least * rows_per_shard)))
