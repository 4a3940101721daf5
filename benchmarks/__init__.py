"""Benchmark scripts: each prints the figures of one BENCHMARKS.md section (the section names it).

Run from the repository root, e.g. ``PYTHONPATH=. .venv/bin/python benchmarks/bench_vs_moordyn.py``
(``make bench`` runs the quick ones). Timing is thread CPU, compared as ratios within one run.

Shared by every script: ``ropos_case`` (the ROPOS tether + cage case, PE2020 Sec. 6) and ``drive``
(drives a solver the way the node does). Cost and speed: ``bench_dg`` / ``bench_dg_kernel`` /
``bench_dg_scaling`` (its figure in docs/dg_solver.md) / ``bench_tick`` (DG substep and tick), ``bench_vs_moordyn`` (DG against MoorDyn
at 1 %, 50 Hz), ``bench_moordyn`` (MoorDyn's ladder), ``bench_accuracy`` + ``summarize_accuracy``
(accuracy against cost), ``bench_solvers`` / ``bench_live_configs`` (real-time factors),
``bench_implicit_damping``, ``bench_free_surface``, ``bench_slack_bending`` (the PE2020 Sec. 6.2 case on the
paper's mesh; no figures recorded in BENCHMARKS.md yet), ``bench_winch`` / ``bench_hybrid_winch`` /
``bench_ropos_descent`` (winch), ``bench_hybrid`` / ``bench_hybrid_jacobian`` / ``bench_hybrid_tick`` (hybrid solver; the last its share of a node tick by part),
``bench_node`` / ``bench_node_tick`` / ``bench_publish_floor`` (what rclpy costs a tick before the node computes) / ``bench_tf`` / ``soak_node`` (the ROS node), ``bench_study_throughput`` (snap-load
studies), ``forecast_skill`` / ``forecast_tick_load`` / ``forecast_perfect_member`` (the snap forecast: its skill, the tick with
the look-aheads running, a member without forecast error against the run), ``bench_network`` / ``bench_tms`` (line networks), ``bench_work_estimate`` (the
load-time work estimate), ``jitter_soak`` (the node's stepping driver under a jittery input). Bit identity: ``regression_vs_baseline`` (all shipped configurations against another checkout)
and ``dg_regression`` (DG end tensions on the ROPOS case, ``--save`` then ``--compare``); the same messages:
``compare_node_outputs`` (the node's, tick by tick) and ``compare_mcap_outputs`` (two MCAP files, field by field).

Every section of BENCHMARKS.md names its script. ``studies/``: accuracy, physics and cross-code studies
whose results are in docs/ (not timings; map in its ``__init__``). ``probes/``: one-off investigations
kept for their commands (cited in docs/performance.md and docs/dg_solver.md).
"""
