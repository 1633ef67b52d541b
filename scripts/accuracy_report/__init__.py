"""The accuracy report (scripts/accuracy.py runs it): config (scenes, maps, the studies' pairs), targets (the
goals, one row each), progress and cache (log, locks, result keys), runner (envshadow's references, renders,
comparisons and benches), values, plots and report (the documents), selftest, and cli (the command line)."""
