#!/usr/bin/env python3
"""What Reconstruction.process costs from Python beyond the C++ pipeline, per frame; prints one JSON object.

Both are timed on the same frames in one process: the Python call's wall time around rec.process(...) against the
engine's own ReconstructionPipeline::process inside it (FrameResult.engine_ms, timed in C++), so that their
difference is the binding's cost (argument checks, releasing and taking the GIL, the result's conversion) and not the
run-to-run spread of a whole frame. Frames are read into memory first. Figures: median, mean and p99 in
milliseconds, for RGB input and for BGR input (bgr=True); neither is converted or copied (the engine reads RGB frames
in their order), so compare their engine_ms too: the engine's RGB path must cost what its BGR path does.

    PYTHONPATH=build/python python3 Module/Python/bench/process_overhead.py --frames 40 --device cpu
"""
import argparse
import json
import pathlib
import tempfile
import time

import numpy as np

import tissuemosaic as tm


def figures(values):
    values = np.asarray(values)
    return {"median": float(np.median(values)), "mean": float(np.mean(values)),
            "p99": float(np.percentile(values, 99))}


def run(rig, pairs, device, bgr):
    reconstruction = tm.Reconstruction(rig, device=device)
    python_ms, engine_ms = [], []
    for index, (left, right) in enumerate(pairs):
        start = time.perf_counter()
        result = reconstruction.process(left, right, index / 30.0, bgr=bgr)
        python_ms.append((time.perf_counter() - start) * 1000.0)
        engine_ms.append(result.engine_ms)
    overhead = [p - e for p, e in zip(python_ms, engine_ms)]
    return {"python_ms": figures(python_ms), "engine_ms": figures(engine_ms), "overhead_ms": figures(overhead),
            "tracked": sum(1 for _ in pairs)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=540)
    parser.add_argument("--device", default="auto", choices=["cpu", "cuda", "auto"])
    parser.add_argument("--scan", type=pathlib.Path, help="a synth scan folder to use instead of rendering one")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as temporary:
        folder = args.scan
        if folder is None:
            folder = pathlib.Path(temporary) / "scan"
            tm.synth.scan(folder, frames=args.frames, width=args.width, height=args.height, seed=1)
        rig = tm.Rig.from_file(folder / "rig.yml", rectified=True)
        rgb = [(left, right) for left, right, _ in
               tm.frames(left_frames=folder / "left", right_frames=folder / "right", max_frames=args.frames)]
    bgr = [(np.ascontiguousarray(left[:, :, ::-1]), np.ascontiguousarray(right[:, :, ::-1])) for left, right in rgb]
    height, width = rgb[0][0].shape[:2]
    report = {"command": "python3 Module/Python/bench/process_overhead.py", "width": width, "height": height,
              "frames": len(rgb), "device": tm.device_description(args.device),
              "rgb": run(rig, rgb, args.device, bgr=False), "bgr": run(rig, bgr, args.device, bgr=True)}
    for entry in ("rgb", "bgr"):
        del report[entry]["tracked"]
    print(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
