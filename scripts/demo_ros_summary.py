#!/usr/bin/python3
"""Summarises what `roslaunch multimodal_nvs demo.launch record:=BAG` recorded (scripts/demo.sh,
stage ros): message counts and rates per output topic, the depth nodelet's statistics, the last
diagnostics, and PNGs of one depth frame, its mask and one conditioning frame decoded from the bag.

Needs /usr/bin/python3 with Debian's python3-rosbag and numpy (messages are decoded from the
definitions stored in the bag, so no workspace has to be sourced). Writes OUT/summary.json and
OUT/*.png, prints one JSON line, and exits 1 when an output topic recorded nothing.
"""
import argparse
import json
import os
import sys

import numpy as np
import rosbag

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from demo_report import colorize, write_png  # noqa: E402  (same directory)

EXPECTED = ["/depth/image", "/depth/camera_info", "/depth/variance", "/depth/mask", "/depth/points",
            "/depth/stats", "/conditioning/image", "/conditioning/camera_info",
            "/conditioning/mask"]
OPTIONAL = ["/conditioning/depth", "/diagnostics"]


def decode_image(msg):
    """sensor_msgs/Image -> numpy array (H x W float32, uint8, or H x W x 3 RGB uint8)."""
    kinds = {"32FC1": (np.float32, 1), "mono8": (np.uint8, 1), "8UC1": (np.uint8, 1),
             "rgb8": (np.uint8, 3), "bgr8": (np.uint8, 3)}
    if msg.encoding not in kinds:
        raise ValueError("unsupported encoding " + msg.encoding)
    dtype, channels = kinds[msg.encoding]
    dtype = np.dtype(dtype).newbyteorder(">" if msg.is_bigendian else "<")
    row_bytes = msg.width * channels * dtype.itemsize
    raw = np.frombuffer(msg.data, np.uint8).reshape(msg.height, msg.step)[:, :row_bytes]
    image = np.ascontiguousarray(raw).view(dtype).reshape(msg.height, msg.width, channels)
    if msg.encoding == "bgr8":
        image = image[:, :, ::-1]
    return image[:, :, 0] if channels == 1 else image


def stamp_span(stamps):
    """(first, last, rate over the header stamps in Hz) of a list of stamps in seconds."""
    if not stamps:
        return None, None, None
    first, last = min(stamps), max(stamps)
    rate = (len(stamps) - 1) / (last - first) if len(stamps) > 1 and last > first else None
    return first, last, rate


def median(values):
    return float(np.median(values)) if values else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--bag", required=True, help="the recorded outputs")
    ap.add_argument("--input-bag", default="", help="the played bag (for the input frame count)")
    ap.add_argument("--out", required=True, help="directory for summary.json and the PNGs")
    ap.add_argument("--frames", type=int, default=0, help="frames in the played bag")
    ap.add_argument("--sensor", default="radar", help="radar | lidar: the played cloud topic")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)

    stamps = {}
    depth, mask, conditioning, conditioning_mask = {}, {}, {}, {}
    stats = []
    diagnostics = {}
    with rosbag.Bag(args.bag) as bag:
        for topic, msg, _ in bag.read_messages():
            if hasattr(msg, "header"):
                stamps.setdefault(topic, []).append(msg.header.stamp.to_sec())
            else:
                stamps.setdefault(topic, [])
            if topic == "/depth/image":
                depth[msg.header.stamp.to_sec()] = msg
            elif topic == "/depth/mask":
                mask[msg.header.stamp.to_sec()] = msg
            elif topic == "/conditioning/image":
                conditioning[msg.header.stamp.to_sec()] = msg
            elif topic == "/conditioning/mask":
                conditioning_mask[msg.header.stamp.to_sec()] = msg
            elif topic == "/depth/stats":
                stats.append(msg)
            elif topic == "/diagnostics":
                for status in msg.status:
                    diagnostics[status.name] = {
                        "level": int.from_bytes(status.level, "little")
                        if isinstance(status.level, bytes) else int(status.level),
                        "message": status.message,
                        "values": {kv.key: kv.value for kv in status.values}}

    input_frames, input_scans = args.frames, None
    if args.input_bag and os.path.exists(args.input_bag):
        with rosbag.Bag(args.input_bag) as bag:
            input_frames = bag.get_message_count(topic_filters=["/camera/image_raw"]) or input_frames
            input_scans = bag.get_message_count(topic_filters=["/%s/points" % args.sensor])

    topics = {}
    for topic in EXPECTED + OPTIONAL + sorted(set(stamps) - set(EXPECTED) - set(OPTIONAL)):
        first, last, rate = stamp_span(stamps.get(topic, []))
        topics[topic] = {"count": len(stamps.get(topic, [])), "first_stamp": first,
                         "last_stamp": last, "rate_hz": rate}
    missing = [t for t in EXPECTED if topics[t]["count"] == 0]

    summary = {"bag": os.path.abspath(args.bag), "input_frames": input_frames,
               "input_scans": input_scans, "sensor": args.sensor, "topics": topics,
               "missing": missing, "images": {}}
    if stats:
        summary["depth_stats"] = {
            "frames": len(stats),
            "points_in_median": median([s.points_in for s in stats]),
            "points_in_view_median": median([s.points_in_view for s in stats]),
            "kept_pixels_median": median([s.kept_pixels for s in stats]),
            "compute_ms_median": median([s.compute_ms for s in stats]),
            "compute_ms_max": float(max(s.compute_ms for s in stats)),
            "latency_ms_median": median([s.latency_ms for s in stats]),
        }
    summary["diagnostics"] = diagnostics

    # One depth frame and one conditioning frame (the keyframe, i.e. the first frame, rendered into
    # that frame's pose), both the middle frame of the recording.
    both = sorted(set(depth) & set(mask))
    if both:
        stamp = both[len(both) // 2]
        d = decode_image(depth[stamp]).astype(np.float64)
        m = decode_image(mask[stamp]) == 255
        valid = m & np.isfinite(d)
        vmax = float(np.percentile(d[valid], 95)) if valid.any() else 1.0
        write_png(os.path.join(args.out, "depth.png"), colorize(np.nan_to_num(d), valid, 0.0, vmax))
        write_png(os.path.join(args.out, "depth_mask.png"), np.where(m, 255, 0).astype(np.uint8))
        summary["images"]["depth"] = {
            "png": "depth.png", "mask_png": "depth_mask.png", "stamp": stamp,
            "size": [int(d.shape[0]), int(d.shape[1])], "vmin": 0.0, "vmax": vmax,
            "kept_fraction": float(m.mean()),
            "depth_median": float(np.median(d[valid])) if valid.any() else None}
    if conditioning:
        ordered = sorted(conditioning)
        stamp = ordered[len(ordered) // 2]
        rgb = decode_image(conditioning[stamp])
        write_png(os.path.join(args.out, "conditioning.png"), rgb)
        entry = {"png": "conditioning.png", "stamp": stamp,
                 "size": [int(rgb.shape[0]), int(rgb.shape[1])]}
        if stamp in conditioning_mask:
            cm = decode_image(conditioning_mask[stamp])
            write_png(os.path.join(args.out, "conditioning_mask.png"), cm)
            entry["mask_png"] = "conditioning_mask.png"
            entry["coverage"] = float((cm == 255).mean())
        first = ordered[0]
        if first in conditioning_mask:
            entry["keyframe_coverage"] = float((decode_image(conditioning_mask[first]) == 255).mean())
        summary["images"]["conditioning"] = entry

    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1, sort_keys=True)
    line = {t: topics[t]["count"] for t in EXPECTED}
    print(json.dumps({"ros_summary": os.path.join(args.out, "summary.json"),
                      "input_frames": input_frames, "input_scans": input_scans, "counts": line,
                      "missing": missing}))
    if missing:
        print("no message recorded on: " + ", ".join(missing), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
