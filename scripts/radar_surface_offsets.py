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
import struct
import sys

import numpy as np


def fail(message):
    sys.exit(f"radar_surface_offsets: {message}")


def read_calib(path):
    values = {}
    try:
        for line in open(path):
            key, _, rest = line.partition(":")
            if rest.split():
                values[key.strip()] = np.array([float(x) for x in rest.split()])
        projection = values["P2"].reshape(3, 4)
        sensor_to_camera = np.eye(4)
        sensor_to_camera[:3] = values["Tr_velo_to_cam"].reshape(3, 4)
    except (OSError, KeyError, ValueError) as error:
        fail(f"{path}: not a KITTI calib with P2 and Tr_velo_to_cam ({error})")
    return projection, sensor_to_camera


def image_size(path):
    """(width, height) from a PNG header or a JPEG start-of-frame marker."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return struct.unpack(">II", data[16:24])
    i = 2
    while i + 9 < len(data):
        if data[i] != 0xFF:
            break
        marker, length = data[i + 1], struct.unpack(">H", data[i + 2:i + 4])[0]
        if marker in (0xC0, 0xC1, 0xC2):
            height, width = struct.unpack(">HH", data[i + 5:i + 9])
            return width, height
        i += 2 + length
    fail(f"{path}: neither a PNG nor a JPEG with a frame header")


def project(points, calib):
    projection, sensor_to_camera = calib
    camera = np.c_[points, np.ones(len(points))] @ sensor_to_camera.T
    uvw = camera[:, :3] @ projection[:, :3].T + projection[:, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        return uvw[:, 0] / uvw[:, 2], uvw[:, 1] / uvw[:, 2], camera[:, 2]


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
    width, height = image_size(images[0])
    radar = read_points(f"{root}/radar/training/velodyne/{frame}.bin", 7)
    lidar = read_points(f"{root}/lidar/training/velodyne/{frame}.bin", 4)
    u, v, z = project(lidar, read_calib(f"{root}/lidar/training/calib/{frame}.txt"))
    inside = (z > 0.5) & (u >= 0) & (u < width) & (v >= 0) & (v < height)
    nearest = np.full((height, width), np.inf)
    np.minimum.at(nearest, (v[inside].astype(int), u[inside].astype(int)), z[inside])
    # The nearest LiDAR depth within `window` pixels (a min filter; edges padded with +inf).
    padded = np.pad(nearest, window, constant_values=np.inf)
    surface = np.full_like(nearest, np.inf)
    for dv in range(2 * window + 1):
        for du in range(2 * window + 1):
            surface = np.minimum(surface, padded[dv:dv + height, du:du + width])
    u, v, z = project(radar, read_calib(f"{root}/radar/training/calib/{frame}.txt"))
    inside = (z > 0.5) & (u >= 0) & (u < width) & (v >= 0) & (v < height)
    lidar_depth = surface[v[inside].astype(int), u[inside].astype(int)]
    seen = np.isfinite(lidar_depth)
    print(f"{frame}: {inside.sum()} radar returns in the image, {seen.sum()} with LiDAR nearby")
    return (z[inside][seen] - lidar_depth[seen]) / lidar_depth[seen]


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
