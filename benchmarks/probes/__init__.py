"""One-off investigations, kept for the commands the docs cite: ``heave_through_surface`` (a top end heaved
through the surface with waves, docs/verification.md), ``profile_dg`` (where the first DG
version's time went, docs/performance.md "First-version figures"), ``bend_slack_probe`` (bending in
slack parts, docs/performance.md "Bending in slack parts: the cause") and ``slack_fold_probe`` (slack with
bending tick by tick, docs/dg_solver.md "Slack with bending")."""
