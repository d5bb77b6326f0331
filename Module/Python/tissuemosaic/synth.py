"""Synthetic stereo pairs and scanning videos with exact ground truth (``import tissuemosaic.synth``)."""
from ._tissuemosaic import synth as _synth

pair = _synth.pair
scan = _synth.scan
__all__ = ["pair", "scan"]
