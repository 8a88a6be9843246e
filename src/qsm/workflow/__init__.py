"""Workflow plumbing: Parquet tables, logs, sharding and code provenance for reruns."""
