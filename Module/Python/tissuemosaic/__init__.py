"""TissueMosaic: dense, textured 3D reconstruction of tissue surfaces from stereo video, for Python.

Images are HxWx3 uint8 **RGB** arrays (OpenCV users pass BGR with ``bgr=True``) or HxW uint8 grey. Units are
millimetres and pixels; poses are 4x4 ``T_world_camera`` (camera to world). Engine errors raise
:class:`tissuemosaic.Error`, a ``ValueError``, with the command line's message. The engine releases the GIL while
it works. Guide: docs/PYTHON.md.

    import tissuemosaic as tm
    rig = tm.Rig.from_file("rig.yml")
    rec = tm.Reconstruction(rig)
    for left, right, time_s in tm.frames(left_video="left.mp4", right_video="right.mp4"):
        result = rec.process(left, right, time_s)
    rec.save("model.ply")
"""
from ._tissuemosaic import (  # noqa: F401  (the public API)
    Error,
    FrameResult,
    Frames,
    Model,
    Reconstruction,
    Rig,
    StereoResult,
    cuda_available,
    cuda_compiled_in,
    default_params,
    device_description,
    evaluate,
    frames,
    read_image,
    read_model,
    read_pfm,
    score_disparity,
    stereo,

    write_pfm,
)
from . import synth  # noqa: E402  (tissuemosaic.synth.pair, tissuemosaic.synth.scan)

__all__ = [
    "Error", "FrameResult", "Frames", "Model", "Reconstruction", "Rig", "StereoResult", "cuda_available",
    "cuda_compiled_in", "default_params", "device_description", "evaluate", "frames", "read_image", "read_model", "read_pfm",
    "score_disparity", "stereo", "synth", "write_pfm",
]

# Show the public classes as tissuemosaic.X (not tissuemosaic._tissuemosaic.X) in help() and tracebacks.
for _class in (Error, FrameResult, Frames, Model, Reconstruction, Rig, StereoResult):
    _class.__module__ = __name__
del _class
