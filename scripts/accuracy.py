#!/usr/bin/env python3
"""Accuracy report: writes docs/ACCURACY.md, docs/PAPER.md and the plots in docs/accuracy/ (scripts/accuracy_report;
`scripts/accuracy.py --help` for the options)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_report.cli import main  # noqa: E402

if __name__ == "__main__":
    main()
