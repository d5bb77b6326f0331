#!/usr/bin/env python3
"""Prints the markdown tables of docs/BENCHMARKS.md's "current figures" sections from benchmark JSON.

Reads the JSON objects that `tissuemosaic bench stereo|orb|track|pnp|reconstruct` print (one object per file, as
Testing/Device/run-gpu-checks.sh saves them in $OUT) and prints, per benchmark, one table with a row per device
(several runs of the same benchmark on the same device are joined with " / ").

    python3 Resources/scripts/benchmark-report.py [--date YYYY-MM-DD] [--commit REV] PATH [PATH ...]

PATH is a JSON file or a folder (its *.json files are read). Files that are empty or not one JSON object (a
benchmark that failed) are named on stderr and skipped. Python 3 standard library only.
"""
import argparse
import datetime
import json
import math
import pathlib
import re
import sys

# The commands print C's %f, which writes NaN and infinity as "nan" and "inf"; JSON spells them otherwise.
_NON_FINITE = re.compile(r'([:\[,]\s*)(-?)(nan|inf)\b')


def parse_json(text):
    return json.loads(_NON_FINITE.sub(
        lambda m: m.group(1) + ("NaN" if m.group(3) == "nan" else m.group(2) + "Infinity"), text))


KINDS = ("bench stereo", "bench orb", "bench track", "bench pnp", "bench reconstruct", "libsgm-timing")


def kind_of(result):
    """The benchmark a JSON object came from: its "command", or "bench pnp" (which prints none)."""
    if "command" in result:
        return result["command"]
    if "cases" in result:
        return "bench pnp"
    return None


def load(paths):
    results = []
    for path in paths:
        path = pathlib.Path(path)
        files = sorted(path.glob("*.json")) if path.is_dir() else [path]
        for file in files:
            try:
                result = parse_json(file.read_text())
            except (OSError, ValueError) as error:
                print(f"benchmark-report: skipping {file}: {error}", file=sys.stderr)
                continue
            if not isinstance(result, dict) or kind_of(result) not in KINDS:
                print(f"benchmark-report: skipping {file}: not a tissuemosaic bench object", file=sys.stderr)
                continue
            result["_file"] = str(file)
            results.append(result)
    return results


def number(value, digits=2):
    if value is None:
        return "-"
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    return f"{value:.{digits}f}"


def runs(group, value, digits=2):
    """One cell: a figure of every run in the group, joined with " / "."""
    return " / ".join(number(value(r), digits) for r in group)


def device_of(result):
    name = result.get("device_name") or result.get("device", "?")
    return name


def grouped(results, key):
    """Groups in first-seen order by key(result)."""
    groups = {}
    for r in results:
        groups.setdefault(key(r), []).append(r)
    return list(groups.values())


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def size_options(r):
    return f"--width {r['width']} --height {r['height']}"


def stereo_sections(results, date):
    out = []
    stereo = [r for r in results if kind_of(r) == "bench stereo"]
    for method in ("paper", "ad-census"):
        chosen = [r for r in stereo if r.get("method", "paper") == method]
        if not chosen:
            continue
        rows = []
        for g in grouped(chosen, lambda r: (device_of(r), r["device"], r["width"], r["height"], r["disparities"])):
            r0 = g[0]
            rows.append([r0["device_name"], date, f"{r0['width']}x{r0['height']}, {r0['disparities']}",
                         runs(g, lambda r: r["median_ms"]["zncc"]),
                         runs(g, lambda r: r["median_ms"]["outliers_holes"]),
                         runs(g, lambda r: r["median_ms"]["refinement"]),
                         "**" + runs(g, lambda r: r["median_ms"]["total"], 3 if r0["device"] == "cuda" else 1) + "**",
                         runs(g, lambda r: r.get("p99_ms", {}).get("total"), 3 if r0["device"] == "cuda" else 1),
                         runs(g, lambda r: r["median_ms"]["upload"], 3),
                         runs(g, lambda r: r["accuracy"]["density"], 3) + " / " +
                         runs(g, lambda r: r["accuracy"]["bad1"], 4)])
        stages = ("zncc", "outliers_holes", "refinement") if method == "paper" else (
            "cost + aggregation (zncc)", "paths + winners (outliers_holes)", "median + checks (refinement)")
        title = "bench stereo" if method == "paper" else "bench stereo --method ad-census"
        out.append(f"### {title}: median ms per stage\n\n" + table(
            ["device", "date", "size, disparities", *stages, "total", "p99 total", "upload", "density / bad-1"], rows) +
            "\n\nCommand: `tissuemosaic bench stereo --device " + "|".join(sorted({r['device'] for r in chosen})) +
            "".join(sorted({f" [{size_options(r)} --disparities {r['disparities']}]" for r in chosen
                            if (r["width"], r["height"]) != (960, 540)})) +
            (" --method ad-census" if method == "ad-census" else "") + "` (repeats: " +
            ", ".join(sorted({f"{r['device']} {r['repeats']}" for r in chosen})) + ")")
    cpu = [r for r in stereo if "opencv_sgbm_3way" in r]
    if cpu:
        rows = []
        for g in grouped(cpu, lambda r: (device_of(r), r.get("method", "paper"), r["width"], r["height"])):
            r0 = g[0]
            rows.append([r0["device_name"], date, r0.get("method", "paper"),
                         runs(g, lambda r: r["median_ms"]["total"], 1),
                         runs(g, lambda r: r["opencv_sgbm_3way"]["median_ms"], 1),
                         "**" + runs(g, lambda r: r["total_over_sgbm"]) + "x**",
                         runs(g, lambda r: r["opencv_sgbm_3way"]["density"], 3) + " / " +
                         runs(g, lambda r: r["opencv_sgbm_3way"]["bad1"], 4)])
        out.append("### CPU stereo against OpenCV StereoSGBM (MODE_SGBM_3WAY), same pair, same process\n\n" + table(
            ["device", "date", "method", "ours, total ms", "SGBM 3-way ms", "ours / SGBM", "SGBM density / bad-1"],
            rows) + "\n\nCommand: `tissuemosaic bench stereo --device cpu`")
    out += peer_section(stereo, [r for r in results if kind_of(r) == "libsgm-timing"], date)
    return out


def peer_section(stereo, libsgm, date):
    """Our GPU stereo beside libSGM at the same size (libSGM takes 64, 128 or 256 disparities: the count at or
    above ours), from the same run."""
    rows = []
    ours = [r for r in stereo if r["device"] == "cuda" and r.get("method", "paper") == "paper"]
    for g in grouped(ours, lambda r: (device_of(r), r["width"], r["height"], r["disparities"])):
        r0 = g[0]
        peers = [p for p in libsgm if (p["width"], p["height"]) == (r0["width"], r0["height"]) and
                 p["disparities"] >= r0["disparities"]]
        for paths in (4, 8):
            chosen = [p for p in peers if p["paths"] == paths]
            if not chosen:
                continue
            count = min(p["disparities"] for p in chosen)
            chosen = [p for p in chosen if p["disparities"] == count]
            ratio = [r["median_ms"]["total"] / p["median_ms"] for r, p in zip(g, chosen)]
            rows.append([r0["device_name"], date, f"{r0['width']}x{r0['height']}", str(r0["disparities"]),
                         runs(g, lambda r: r["median_ms"]["total"], 3), f"{count}, {paths}-path",
                         runs(chosen, lambda p: p["median_ms"], 3),
                         "**" + " / ".join(f"{x:.2f}" for x in ratio) + "x**"])
    if not rows:
        return []
    return ["### GPU stereo against libSGM, same run\n\n" + table(
        ["device", "date", "size", "our disparities", "ours, total ms", "libSGM disparities, paths", "libSGM ms",
         "ours / libSGM"], rows) +
        "\n\nCommands: `tissuemosaic bench stereo --device cuda --width W --height H --disparities N`; "
        "`libsgm-timing --width W --height H --disparities N --paths P` (Testing/Device/libsgm-peer)"]


def orb_section(results, date):
    orb = [r for r in results if kind_of(r) == "bench orb"]
    if not orb:
        return []
    rows = []
    for g in grouped(orb, lambda r: (device_of(r), r["width"], r["height"], r["levels"])):
        r0 = g[0]
        has_cv = "opencv" in r0
        rows.append([r0["device_name"], date, f"{r0['width']}x{r0['height']}, {r0['levels']}",
                     runs(g, lambda r: r["features"][0], 0),
                     runs(g, lambda r: r["median_ms"]["extract"], 3),
                     runs(g, lambda r: r["median_ms"]["match"], 3),
                     "**" + runs(g, lambda r: r["median_ms"]["extract2_match"], 3) + "**",
                     runs(g, lambda r: r["opencv"]["median_ms"]["extract"], 3) if has_cv else "-",
                     runs(g, lambda r: r["opencv"]["median_ms"]["match"], 3) if has_cv else "-"])
    return ["### bench orb: median ms\n\n" + table(
        ["device", "date", "size, levels", "features", "extract", "match (k = 3)", "2 extract + match",
         "OpenCV ORB extract", "OpenCV BFMatcher"], rows) +
        "\n\nCommand: `tissuemosaic bench orb --device cuda|cpu`"]


def track_section(results, date):
    track = [r for r in results if kind_of(r) == "bench track"]
    if not track:
        return []
    rows = []
    for g in grouped(track, lambda r: (device_of(r), r["features"], r["width"], r["height"], r["frames"])):
        r0 = g[0]
        parts = lambda key: runs(g, lambda r: r["orb_voting_parts_median_ms"][key])
        rows.append([r0["device_name"], date, f"{r0['frames']}, {r0['features']}",
                     runs(g, lambda r: r["median_ms"]["orb_voting"]),
                     runs(g, lambda r: r["median_ms"]["pnp"]),
                     "**" + runs(g, lambda r: r["median_ms"]["tracking"]) + "**",
                     f"{parts('extract_and_lift')}; {parts('match')}; {parts('subpixel')}; {parts('vote')}",
                     runs(g, lambda r: r["lost"], 0)])
    return ["### bench track: median ms per frame\n\n" + table(
        ["device", "date", "frames, features", "ORB + voting", "DynamicR1PPnP", "tracking",
         "extract + lift; match; sub-pixel; vote", "lost"], rows) +
        "\n\nCommand: `tissuemosaic bench track --device cuda --frames " +
        "|".join(sorted({str(r["frames"]) for r in track})) + "`"]


def pnp_section(results, date):
    pnp = [r for r in results if kind_of(r) == "bench pnp"]
    out = []
    for r in pnp:
        ratios = sorted({c["outlier_ratio"] for c in r["cases"]})
        rows = {}
        for c in r["cases"]:
            rows.setdefault((c["method"], c["n"]), {})[c["outlier_ratio"]] = c
        body = []
        for (method, n), cells in rows.items():
            body.append([method, str(n)] + [
                f"{cells[q]['success_rate']:.2f} / {cells[q]['median_ms']:.2f}" if q in cells else "-" for q in ratios])
        out.append(f"### bench pnp: success rate / median ms per solve ({r['device']}, {r['threads']} thread, "
                   f"{r['repeats']} scenes per case, {date})\n\n" +
                   table(["method", "N", *[f"outliers {q:g}" for q in ratios]], body) +
                   f"\n\nSuccess: {r['success']}. Command: `tissuemosaic bench pnp --repeats {r['repeats']}`")
    return out


STAGES = ("stereo", "orb_voting", "dynamic_r1ppnp", "refinement", "tsdf", "total")
STAGE_NAMES = ("stereo", "ORB + voting", "DynamicR1PPnP", "refinement", "TSDF", "total")


def reconstruct_sections(results, date):
    rec = [r for r in results if kind_of(r) == "bench reconstruct"]
    out = []
    for g in grouped(rec, lambda r: (r["frames"], r["width"], r["height"], tuple(r.get("disparity_range_px", ())))):
        r0 = g[0]
        for devices in grouped(g, device_of):
            d0 = devices[0]
            timing = lambda key, frames, stat: runs(devices, lambda r: r["timing"][frames].get(stat, {}).get(key))
            cell = lambda key, frames: (f"{timing(key, frames, 'median_ms')} ({timing(key, frames, 'mean_ms')}, "
                                        f"{timing(key, frames, 'p99_ms')})")
            rows = [[name, cell(key, "key_frames"), "-" if key in ("refinement", "tsdf") else cell(key, "other_frames")]
                    for key, name in zip(STAGES, STAGE_NAMES)]
            rows[-1] = ["**" + c + "**" for c in rows[-1]]
            text = (f"### bench reconstruct, {r0['frames']} frames {r0['width']}x{r0['height']}: "
                    f"{d0['device_name']}, {date}\n\n"
                    "Median (mean, p99) ms per frame, the paper's runtime table (stereo runs beside tracking, so the "
                    "total is less than the sum):\n\n" +
                    table(["stage", "key frame", "other frame"], rows))
            summary = [
                ["frames lost", runs(devices, lambda r: r["lost"], 0)],
                ["key frames", runs(devices, lambda r: r["key_frames"], 0)],
                ["model points", runs(devices, lambda r: r["model_points"], 0)],
                ["key-frame position RMSE (no alignment), mm", runs(devices, lambda r: r["key_frame_position_rmse_mm"], 4)],
                ["model RMSE / p95 to the true surface, mm",
                 runs(devices, lambda r: r["model_rmse_mm"], 4) + " / " + runs(devices, lambda r: r["model_p95_mm"], 4)],
                ["peak device / host memory, MiB",
                 runs(devices, lambda r: r["peak_device_mib"], 0) + " / " + runs(devices, lambda r: r["peak_host_mib"], 0)],
            ]
            text += "\n\n" + table(["", "value"], summary)
            if len(d0.get("memory", [])) > 1:
                memory_rows = [[str(m["frame"]), f"{m['host_resident_mib']:.0f}", f"{m['peak_device_mib']:.0f}",
                                f"{m['model_points'] / 1e6:.2f} M"] for m in d0["memory"]]
                text += ("\n\nMemory at each quarter of the run (first run):\n\n" +
                         table(["frames", "host resident MiB", "device peak MiB", "model points"], memory_rows))
            size = "" if (r0["width"], r0["height"]) == (960, 540) else f" {size_options(r0)}"
            if "disparity_range_px" in r0 and size:
                low, high = r0["disparity_range_px"]
                size += f" --disparities {high - low + 1}"
            text += (f"\n\nCommand: `tissuemosaic bench reconstruct --device {d0['device']} --frames {r0['frames']}{size}"
                     f"{' --stream --chunk 100 --supersampling 1' if r0['frames'] > 1000 else ''}`")
            out.append(text)
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("paths", nargs="+", help="JSON files or folders of them (e.g. the $OUT of run-gpu-checks.sh)")
    parser.add_argument("--date", default=datetime.date.today().isoformat(), help="date of the runs (default today)")
    parser.add_argument("--commit", help="the tree the runs were of, added to the date")
    args = parser.parse_args(argv)
    results = load(args.paths)
    if not results:
        print("benchmark-report: no benchmark JSON found", file=sys.stderr)
        return 1
    date = args.date + (f", {args.commit}" if args.commit else "")
    sections = (stereo_sections(results, date) + orb_section(results, date) + track_section(results, date) +
                pnp_section(results, date) + reconstruct_sections(results, date))
    print("\n\n".join(sections))
    return 0


if __name__ == "__main__":
    sys.exit(main())
