"""The trace viewer: `gpp trace summary|html|perfetto|mcap` read a run's trace (JSON lines, one
gpp.runtime.events record per line) and show it as a terminal timeline, one self-contained
interactive HTML page, Chrome trace-event JSON for ui.perfetto.dev, or an MCAP file for Foxglove
(`gpp.traceview.mcapfile`).

All of them read the trace through `gpp.traceview.model` (load_trace, build_run_model); they
know nothing of the executor, only the trace's events.
"""

from gpp.traceview.model import Activity, Lane, RunModel, Sample, Series, TraceReadError, Wait, build_run_model
from gpp.traceview.model import load_trace as load_trace

__all__ = [
    "Activity",
    "Lane",
    "RunModel",
    "Sample",
    "Series",
    "TraceReadError",
    "Wait",
    "build_run_model",
    "load_trace",
]
