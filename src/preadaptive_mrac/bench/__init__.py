"""What bench/run_bench.sh runs besides the binaries: timing whole processes against each other
(timing), instruction counts from callgrind listings (callgrind), and docs/performance.md from
the collected results (report). bench/perf_report.py is the entry point.
"""
