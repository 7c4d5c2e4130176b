"""``python -m ringlube.gas --out DIR [NAME ...]``: regenerate the shipped traces
(:func:`ringlube.gas.traces.main`)."""

from .traces import main

main()
