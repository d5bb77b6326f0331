#!/usr/bin/env python3
"""Scores tissuemosaic.stereo on a folder of stereo pairs with ground-truth disparity; prints one JSON object.

FOLDER holds one subfolder per scene, in either layout:
  Middlebury v2 (../shared/data/middlebury-v2): imL.png imR.png groundtruth.png (disparity times info.txt's first
      line; 0 = unknown), nonocc.png (the pixels scored) and info.txt (scale, then the largest disparity, which fixes
      the range to 0..max);
  `tissuemosaic synth pair --out` (or tissuemosaic.synth.pair(out=...)): left.png right.png disparity.pfm (NaN =
      unknown); the range is chosen from the pair.
Figures per scene as `tissuemosaic stereo --ground-truth` prints them: density, bad1, bad2 (shares of the estimated
pixels off by more than 1 or 2 px), mean_abs_error_px; then their mean over the scenes.

    PYTHONPATH=build/python python3 Module/Python/examples/stereo_on_pairs.py ../shared/data/middlebury-v2
"""
import argparse
import json
import pathlib
import sys

import numpy as np

import tissuemosaic as tm


def middlebury_scene(folder: pathlib.Path):
    scale, largest = (float(line) for line in (folder / "info.txt").read_text().split()[:2])
    truth = tm.read_image(folder / "groundtruth.png")[:, :, 0].astype(np.float32) / scale
    truth[truth == 0] = np.nan  # 0 = unknown
    mask = np.ascontiguousarray(tm.read_image(folder / "nonocc.png")[:, :, 0])
    return folder / "imL.png", folder / "imR.png", truth, mask, (0, int(largest))


def synthetic_scene(folder: pathlib.Path):
    return folder / "left.png", folder / "right.png", tm.read_pfm(folder / "disparity.pfm"), None, "auto"


def scenes(root: pathlib.Path):
    for folder in sorted(path for path in root.iterdir() if path.is_dir()):
        if (folder / "imL.png").exists():
            yield folder.name, middlebury_scene(folder)
        elif (folder / "disparity.pfm").exists():
            yield folder.name, synthetic_scene(folder)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder", type=pathlib.Path)
    parser.add_argument("--method", default="paper", choices=["paper", "ad-census"])
    parser.add_argument("--device", default="auto", choices=["cpu", "cuda", "auto"])
    args = parser.parse_args()

    report = {"method": args.method, "device": tm.device_description(args.device), "scenes": {}}
    for name, (left_path, right_path, truth, mask, disparity_range) in scenes(args.folder):
        left, right = tm.read_image(left_path), tm.read_image(right_path)
        result = tm.stereo(left, right, params={"stereo": {"method": args.method}}, device=args.device,
                           disparity_range=disparity_range)
        score = tm.score_disparity(result.disparity, truth, mask)
        score["disparity_range"] = list(result.disparity_range)
        report["scenes"][name] = score
    if not report["scenes"]:
        print(f"no scene with ground truth under {args.folder}", file=sys.stderr)
        return 1
    for key in ("density", "bad1", "bad2", "mean_abs_error_px"):
        report["mean_" + key] = float(np.mean([scene[key] for scene in report["scenes"].values()]))
    print(json.dumps(report, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
