"""Snap-load studies at scale (``tether-sim-study``): many offline runs from one study file.

Above the ``ros`` layer like the other programs: each case runs through the offline runner of
``tether-sim-offline`` (imported only inside the worker function); nothing here imports rclpy itself.
Modules: ``spec`` (study files), ``case`` (one case, keys), ``stats`` (snap statistics),
``results`` (journal, Parquet, CSV), ``execute`` (local processes, Dask), ``runner``, ``report``, ``cli``.
"""
