"""One-off investigations, kept for the commands the docs cite: ``heave_through_surface`` (a top end heaved
through the surface with waves, docs/verification.md), ``profile_dg`` (where the first DG
version's time went, docs/performance.md "First-version figures") and ``bend_slack_probe`` (bending in
slack parts, docs/performance.md "Bending in slack parts: the cause")."""
