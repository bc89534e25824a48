"""Benchmarks run by ``make bench``: every ``bench_*.py`` module here exposes ``run(out_dir)``.

Each writes its numbers to ``<out_dir>/<name>.json`` (and charts as PNG). Speed targets are
ratios measured within one run, never absolute times.
"""
