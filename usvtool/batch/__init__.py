"""The batch engine of ``usvtool batch`` (docs/batch.md): a pipeline's jobs on a local pool of
worker processes or a Dask cluster, resumable, with one long-format results table.

Modules: :mod:`~usvtool.batch.commands` (the jobs' command lines and a grid's files),
:mod:`~usvtool.batch.jobs` (the jobs and their keys), :mod:`~usvtool.batch.make` (the Make
fragment), :mod:`~usvtool.batch.worker` (one job in a worker), :mod:`~usvtool.batch.local`
and :mod:`~usvtool.batch.cluster` (the executors), :mod:`~usvtool.batch.results_tables`,
:mod:`~usvtool.batch.progress`, and :mod:`~usvtool.batch.engine` (:func:`run_batch`). Like
every stage it imports no other stage: the jobs are command lines, run by a function the caller
gives.
"""

from usvtool.batch.engine import BatchOptions, BatchResult, run_batch

__all__ = ["BatchOptions", "BatchResult", "run_batch"]
