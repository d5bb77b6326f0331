#!/usr/bin/env python3
"""Reconstructs a stereo video with tissuemosaic and writes the model (and the key frames' trajectory), as
`tissuemosaic reconstruct` does; prints a JSON summary.

    PYTHONPATH=build/python python3 Module/Python/examples/reconstruct_video.py --video sbs.avi \
        --calib rig.yml --rectified --out model.ply --trajectory keyframes.txt

Input: one 3D video (--video, --layout sbs|sbs-half|tb|tb-half|rows), two videos (--left-video --right-video) or two
frame folders (--left-frames --right-frames). Geometry: --calib (any layout of docs/CALIBRATION.md; --rectified when
the frames already are) or --focal-px --baseline-mm for rectified frames.
"""
import argparse
import collections
import json
import sys

import numpy as np

import tissuemosaic as tm


def first_tum_pose(path):
    """The first pose of a TUM file (t tx ty tz qx qy qz qw) as a 4x4 T_world_camera."""
    with open(path) as tum:
        rows = [line.split() for line in tum if line.strip() and not line.startswith("#")]
    _, tx, ty, tz, qx, qy, qz, qw = map(float, rows[0])
    pose = np.eye(4)
    pose[:3, :3] = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                    [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                    [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]]
    pose[:3, 3] = [tx, ty, tz]
    return pose


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--video")
    parser.add_argument("--layout", default="sbs")
    parser.add_argument("--left-video")
    parser.add_argument("--right-video")
    parser.add_argument("--left-frames")
    parser.add_argument("--right-frames")
    parser.add_argument("--calib")
    parser.add_argument("--rectified", action="store_true")
    parser.add_argument("--focal-px", type=float)
    parser.add_argument("--baseline-mm", type=float)
    parser.add_argument("--out", required=True, help="model.ply")
    parser.add_argument("--trajectory", help="key frames' poses (TUM)")
    parser.add_argument("--start-tum", help="the first frame's pose: the first pose of this TUM file (a ground truth)")
    parser.add_argument("--params", help="parameters file (YAML)")
    parser.add_argument("--device", default="auto", choices=["cpu", "cuda", "auto"])
    args = parser.parse_args()

    if args.calib:
        rig = tm.Rig.from_file(args.calib, rectified=args.rectified)
    elif args.focal_px and args.baseline_mm:
        rig = tm.Rig.rectified(focal_px=args.focal_px, baseline_mm=args.baseline_mm)
    else:
        parser.error("give --calib, or --focal-px and --baseline-mm")
    source = tm.frames(video=args.video, layout=args.layout, left_video=args.left_video, right_video=args.right_video,
                       left_frames=args.left_frames, right_frames=args.right_frames)
    reconstruction = tm.Reconstruction(rig, params=args.params, device=args.device,
                                       start_pose=first_tum_pose(args.start_tum) if args.start_tum else None)
    statuses = collections.Counter()
    for left, right, time_s in source:  # raw frames as read: the reconstruction rectifies them with a calibration
        result = reconstruction.process(left, right, time_s)
        statuses[result.status] += 1
    reconstruction.save(args.out, trajectory=args.trajectory)
    print(json.dumps({"input": source.description, "frames": reconstruction.frame_count, **statuses,
                      "key_frames": len(reconstruction.trajectory()), "model_points": len(reconstruction.model()),
                      "disparity_range": reconstruction.disparity_range, "model": args.out,
                      "timing": reconstruction.timing()}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
