#!/usr/bin/python3
"""How far radar returns lie from the surface the LiDAR sees at their pixel (numpy only).

  radar_surface_offsets.py ROOT FRAME [FRAME ...] [--window-px R]

ROOT is a View-of-Delft-layout folder with radar and LiDAR (../shared/data/vod, astyx, nuscenes,
or a make_synthetic_scene output). Each radar return in the image is compared with the nearest
LiDAR depth within R pixels of its projection (the nearest surface there); prints percentiles of
(radar depth - LiDAR depth) / LiDAR depth and the shares off by more than 20 %. Why: it tells a
synthetic radar (make_synthetic_scene --radar-pass-through, --radar-angle-sigma) from a real one.
Measured (R = 3), median |offset| / share 20 % or more behind the LiDAR surface: VoD 00549/01047
0.17 / 0.45, Astyx 0.27 / 0.51, nuScenes 0.30 / 0.42; the 14 synthetic scenes of
eval/synthetic_scenes.tsv 0.010-0.25 / 0.03-0.25 (typically 0.02 / 0.07); with
--radar-pass-through 0.9 (dev scenes) 0.09-0.15 / 0.27-0.42.
"""
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from demo_report import jpeg_size, project, read_calib  # noqa: E402  (the demo's KITTI helpers)


def fail(message):
    sys.exit(f"radar_surface_offsets: {message}")


def calib(path):
    try:
        entries = read_calib(path)
        entries["P2"].reshape(3, 4), entries["Tr_velo_to_cam"][:12].reshape(3, 4)
    except (OSError, KeyError, ValueError) as error:
        fail(f"{path}: not a KITTI calib with P2 and Tr_velo_to_cam ({error})")
    return entries


def read_points(path, fields):
    try:
        values = np.fromfile(path, np.float32)
    except OSError as error:
        fail(f"{path}: {error}")
    if values.size % fields:
        fail(f"{path}: {values.size} floats, not a multiple of {fields}")
    return values.reshape(-1, fields)[:, :3].astype(np.float64)


def frame_offsets(root, frame, window):
    images = glob.glob(f"{root}/lidar/training/image_2/{frame}.*")
    if not images:
        fail(f"{root}/lidar/training/image_2/{frame}.*: no camera image")
    try:
        width, height = jpeg_size(images[0])
    except (OSError, ValueError, IndexError) as error:
        fail(f"{images[0]}: no image size ({error})")
    radar = read_points(f"{root}/radar/training/velodyne/{frame}.bin", 7)
    lidar = read_points(f"{root}/lidar/training/velodyne/{frame}.bin", 4)
    u, v, z = project(lidar, calib(f"{root}/lidar/training/calib/{frame}.txt"), width, height)
    nearest = np.full((height, width), np.inf)
    np.minimum.at(nearest, (v.astype(int), u.astype(int)), z)
    # The nearest LiDAR depth within `window` pixels (a min filter; edges padded with +inf).
    padded = np.pad(nearest, window, constant_values=np.inf)
    surface = np.full_like(nearest, np.inf)
    for dv in range(2 * window + 1):
        for du in range(2 * window + 1):
            surface = np.minimum(surface, padded[dv:dv + height, du:du + width])
    u, v, z = project(radar, calib(f"{root}/radar/training/calib/{frame}.txt"), width, height)
    lidar_depth = surface[v.astype(int), u.astype(int)]
    seen = np.isfinite(lidar_depth)
    print(f"{frame}: {len(z)} radar returns in the image, {seen.sum()} with LiDAR nearby")
    return (z[seen] - lidar_depth[seen]) / lidar_depth[seen]


def main(argv):
    window = 3
    if "--window-px" in argv:
        i = argv.index("--window-px")
        try:
            window = int(argv[i + 1])
        except (IndexError, ValueError):
            fail("--window-px needs an integer")
        del argv[i:i + 2]
    if len(argv) < 2 or window < 0:
        fail("usage: radar_surface_offsets.py ROOT FRAME [FRAME ...] [--window-px R]")
    root, frames = argv[0], argv[1:]
    offsets = np.concatenate([frame_offsets(root, f, window) for f in frames])
    if offsets.size == 0:
        fail(f"{root}: no radar return has a LiDAR return within {window} px")
    magnitude = np.abs(offsets)
    percentiles = np.percentile(offsets, [10, 25, 50, 75, 90])
    print(f"returns {offsets.size}; offset percentiles 10/25/50/75/90: "
          + " ".join(f"{p:+.3f}" for p in percentiles))
    print(f"median |offset| {np.median(magnitude):.3f}; off by > 20 %: {np.mean(magnitude > 0.2):.3f}"
          f" (behind {np.mean(offsets > 0.2):.3f}, in front {np.mean(offsets < -0.2):.3f})")


if __name__ == "__main__":
    main(sys.argv[1:])
