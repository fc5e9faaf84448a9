#!/usr/bin/python3
"""Where a depth map's novel views lose against the exact depth, region by region (numpy only).

  novel_view_gap_by_region.py ROOT PREFIX [--tools DIR] [--size H W] [--work DIR]

ROOT is a make_synthetic_scene output (exact depth in depth_gt/00000.npy); PREFIX_depth.npy is a
model's depth of frame 0 at the image's size (complete_depth --output PREFIX; PREFIX_valid.npy, when
there, drops the pixels retention did not keep). render_conditioning (GEN3C's splatting, into every
recorded pose of the scene) draws the model's depth, the oracle (the exact depth, the sky at
GEN3C's 100 m clamp) and the model's depth with the oracle pasted into one region at a time:

  above  above the highest LiDAR return of each image column (no ring reaches it), not sky
         (and, inside it, only the pixels the model puts > 10 % too near, or > 10 % too far)
  below  every other pixel with a surface
  sky    no surface in the exact depth, or one beyond 99 m

With --by-error the regions are the model's errors instead (any input, radar too):

  near   pixels with a surface that the model puts > 10 % too near
  far    ... > 10 % too far
  within ... within 10 %
  sky    as above

Each row prints covered PSNR dB / coverage / preview PSNR dB and how much of the model's covered
PSNR gap to the oracle pasting that region closes. Why: it says which part of the depth to work on.
Measured on 4 December (LiDAR, all returns, ground_gp as config/lidar.yaml but 100 % kept, dev
scenes dev_s1, s7, s23, s41): the region above the highest ring closes 1.2-2.5 dB of 2.0-2.8 dB,
most of it from the 1-6 % of pixels put > 10 % too near (a sign's or a truck's depth carried up
the column to the image top); the rest of the image closes 0.2-0.7 dB, the sky 0.1-0.3 dB.
Measured on 7 December with --by-error (radar, the default image_guided, 100 % kept, dev_s1, s11,
s31, s41): 42-43 % of the image is > 10 % too near and pasting it closes 35-82 % of the gap (the
facades, which take the lateral offset of the parked cars in front of them); the too-far pixels
(7-18 %) close 1-37 %, the sky 2-10 %.
"""
import argparse
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from demo_report import project, read_calib  # noqa: E402  (the demo's KITTI helpers)

SKY_BEYOND_M = 99.0  # GEN3C clamps at 100 m: a surface beyond this renders like the sky
FAR_CLAMP_M = 100.0
WRONG_BY = 0.10      # "too near" / "too far": more than this relative error
TOP_SMOOTHING_COLUMNS = 3  # a column's highest return: the highest within +-3 columns (ring gaps)


def fail(message):
    sys.exit(f"novel_view_gap_by_region: {message}")


def load_npy(path, shape=None):
    try:
        array = np.load(path)
    except (OSError, ValueError) as error:
        fail(f"{path}: {error}")
    if array.ndim != 2 or (shape is not None and array.shape != shape):
        fail(f"{path}: shape {array.shape}, expected {shape or 'a 2-D array'}")
    return array


def above_highest_return(root, height, width):
    """Pixels above the highest LiDAR return of their column (columns without one: none)."""
    path = f"{root}/lidar/training/velodyne/00000.bin"
    try:
        values = np.fromfile(path, np.float32)
    except OSError as error:
        fail(f"{path}: {error}")
    if values.size == 0 or values.size % 4:
        fail(f"{path}: {values.size} floats, not x y z intensity per point")
    calib_path = f"{root}/lidar/training/calib/00000.txt"
    try:
        calib = read_calib(calib_path)
        u, v, _ = project(values.reshape(-1, 4)[:, :3].astype(np.float64), calib, width, height)
    except (OSError, KeyError, ValueError) as error:
        fail(f"{calib_path}: not a KITTI calib with P2 and Tr_velo_to_cam ({error})")
    top = np.full(width, height)
    np.minimum.at(top, u.astype(int), v.astype(int))
    padded = np.pad(top, TOP_SMOOTHING_COLUMNS, mode="edge")
    top = np.min([padded[i:i + width] for i in range(2 * TOP_SMOOTHING_COLUMNS + 1)], axis=0)
    top = np.where(top < height, top, 0)  # a column no return reaches has no "above"
    return np.arange(height)[:, None] < top[None, :]


def render(tools, root, depth, work, name, size, frames):
    """render_conditioning's mean metrics for one depth map."""
    depth_path = f"{work}/{name}_depth.npy"
    np.save(depth_path, depth.astype(np.float32))
    out = f"{work}/{name}.render"
    command = [f"{tools}/render_conditioning",
               "--image", f"{root}/lidar/training/image_2/00000.jpg", "--depth", depth_path,
               "--calib", f"{root}/radar/training/calib/00000.txt",
               "--vod-root", root, "--frames", f"0-{frames - 1}", "--num-frames", str(frames),
               "--size", str(size[0]), str(size[1]), "--output", out]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"render_conditioning failed on {name}: {result.stderr.strip()[-400:]}")
    with open(f"{out}/metrics.json") as f:
        mean = json.load(f)["mean"]
    shutil.rmtree(out, ignore_errors=True)
    return mean["covered_psnr"], mean["coverage"], mean["psnr"]


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("root")
    parser.add_argument("prefix")
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--tools",
                        default=os.path.join(here, "..", "devel", "lib", "multimodal_nvs"),
                        help="folder of render_conditioning (default: the repository's devel)")
    parser.add_argument("--size", type=int, nargs=2, default=[352, 640], metavar=("H", "W"))
    parser.add_argument("--work", help="keep the pasted depth maps in this folder")
    parser.add_argument("--by-error", action="store_true",
                        help="regions by the model's error (too near, too far, within 10 %%, sky) "
                             "instead of by the LiDAR's highest return")
    args = parser.parse_args(argv)
    if not os.access(f"{args.tools}/render_conditioning", os.X_OK):
        fail(f"{args.tools}/render_conditioning: not an executable (--tools)")
    frames = len(glob.glob(f"{args.root}/lidar/training/pose/*.json"))
    if frames < 2:
        fail(f"{args.root}/lidar/training/pose: {frames} poses, need the scene's trajectory")

    exact = load_npy(f"{args.root}/depth_gt/00000.npy").astype(np.float64)
    model = load_npy(f"{args.prefix}_depth.npy", exact.shape).astype(np.float64)
    model = np.where(np.isfinite(model), model, 0.0)
    if os.path.exists(f"{args.prefix}_valid.npy"):
        model = np.where(load_npy(f"{args.prefix}_valid.npy", exact.shape) > 0, model, 0.0)
    sky = ~(exact > 0) | (exact > SKY_BEYOND_M)
    oracle = np.where(exact > 0, exact, FAR_CLAMP_M)
    relative = (model - oracle) / oracle
    if args.by_error:
        # A pixel without a prediction (0) counts as too near: pasting gives it the exact depth.
        near = ~sky & (relative < -WRONG_BY)
        far = ~sky & (relative > WRONG_BY)
        regions = [
            ("> 10 % too near", near),
            ("> 10 % too far", far),
            ("within 10 %", ~sky & ~near & ~far),
            ("sky", sky),
        ]
    else:
        above = above_highest_return(args.root, *exact.shape) & ~sky
        regions = [
            ("above the highest return", above),
            ("  of it > 10 % too near", above & (model > 0) & (relative < -WRONG_BY)),
            ("  of it > 10 % too far", above & (relative > WRONG_BY)),
            ("below it", ~above & ~sky),
            ("sky", sky),
        ]

    work = args.work or tempfile.mkdtemp(prefix="nvs_gap_")
    os.makedirs(work, exist_ok=True)
    try:
        base = render(args.tools, args.root, model, work, "model", args.size, frames)
        best = render(args.tools, args.root, oracle, work, "oracle", args.size, frames)
        gap = best[0] - base[0]
        header = f"{'covered PSNR':>12} {'coverage':>9} {'preview':>8} {'gap closed':>11}"
        print(f"{'depth':<46} {header}")
        print(f"{'model':<46} {base[0]:12.2f} {base[1]:9.3f} {base[2]:8.2f}")
        for i, (name, mask) in enumerate(regions):
            pasted = render(args.tools, args.root, np.where(mask, oracle, model), work,
                            f"region{i}", args.size, frames)
            closed = (pasted[0] - base[0]) / gap if abs(gap) > 1e-9 else 0.0
            label = f"model, oracle {name} ({mask.mean():.3f})"
            print(f"{label:<46} {pasted[0]:12.2f} {pasted[1]:9.3f} {pasted[2]:8.2f} {closed:10.0%}")
        print(f"{'oracle':<46} {best[0]:12.2f} {best[1]:9.3f} {best[2]:8.2f}")
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1:])
