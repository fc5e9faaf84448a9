#!/usr/bin/python3
"""Writes the `make demo` report: demo_output/index.html and the pictures it shows.

Needs only /usr/bin/python3 and numpy. Images are encoded with a small PNG writer (zlib); the radar
and LiDAR overlay is drawn by the browser (SVG over the camera image), so no image library is
needed to decode the JPEG.

Inputs (all paths relative to --out unless absolute):
  --root DIR          VoD layout root of the demo scene
  --frame N           reference frame (the one depth completion ran on)
  --frames A-B        recorded frames of the trajectory
  --depth-prefix P    complete_depth output prefix (P_depth.npy, P_variance.npy, P_valid.npy, PNGs)
  --conditioning DIR  render_conditioning output directory (optional)
  --timings FILE      "stage<TAB>seconds<TAB>status" lines written by demo.sh
  --ros-summary FILE  summary.json of scripts/demo_ros_summary.py (the bag played through
                      launch/demo.launch and the recorded outputs; optional)
"""
import argparse
import html
import json
import os
import shutil
import struct
import sys
import zlib

import numpy as np


# ---------------------------------------------------------------------------------------------
# Small file-format helpers


def write_png(path, image):
    """uint8 H x W (grey) or H x W x 3 (RGB) -> PNG."""
    image = np.ascontiguousarray(image, dtype=np.uint8)
    h, w = image.shape[:2]
    channels = 1 if image.ndim == 2 else image.shape[2]
    rows = image.reshape(h, w * channels)
    raw = np.hstack([np.zeros((h, 1), np.uint8), rows]).tobytes()

    def chunk(tag, data):
        return (struct.pack(">I", len(data)) + tag + data +
                struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    color_type = {1: 0, 3: 2}[channels]
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, color_type, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def read_calib(path):
    entries = {}
    with open(path) as f:
        for line in f:
            if ":" not in line:
                continue
            key, values = line.split(":", 1)
            numbers = values.split()
            if numbers:
                entries[key.strip()] = np.array([float(x) for x in numbers])
    return entries


def jpeg_size(path):
    """(width, height) from the SOF marker of a JPEG, or from the IHDR of a PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return struct.unpack(">II", data[16:24])
    i = 2
    while i < len(data):
        if data[i] != 0xFF:
            i += 1
            continue
        marker = data[i + 1]
        if marker in (0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
            h, w = struct.unpack(">HH", data[i + 5:i + 9])
            return w, h
        length = struct.unpack(">H", data[i + 2:i + 4])[0]
        i += 2 + length
    raise ValueError(path + ": no JPEG frame header")


def npy_shape(path):
    with open(path, "rb") as f:
        magic = f.read(8)
        if magic[:6] != b"\x93NUMPY":
            return None
        size = struct.unpack("<H" if magic[6] == 1 else "<I", f.read(2 if magic[6] == 1 else 4))[0]
        header = f.read(size).decode("latin1")
    try:
        return eval(header, {"__builtins__": {}}, {"True": True, "False": False})  # dict literal
    except Exception:  # noqa: BLE001 - a report must not fail on an odd header
        return None


# ---------------------------------------------------------------------------------------------
# Pictures


def jet(values, vmin, vmax):
    """OpenCV-like JET colour map of a float array -> uint8 RGB."""
    t = np.clip((values - vmin) / max(vmax - vmin, 1e-12), 0.0, 1.0)
    r = np.clip(1.5 - np.abs(4.0 * t - 3.0), 0.0, 1.0)
    g = np.clip(1.5 - np.abs(4.0 * t - 2.0), 0.0, 1.0)
    b = np.clip(1.5 - np.abs(4.0 * t - 1.0), 0.0, 1.0)
    return (np.stack([r, g, b], -1) * 255.0 + 0.5).astype(np.uint8)


def jet_css(vmin, vmax, unit):
    stops = ", ".join("rgb(%d,%d,%d) %d%%" % (*jet(np.array(t), 0, 1), int(100 * t))
                      for t in np.linspace(0, 1, 9))
    return ('<div class="bar"><span>%s</span><div class="grad" style="background: linear-gradient('
            'to right, %s)"></div><span>%s %s</span></div>' % (fmt(vmin), stops, fmt(vmax), unit))


def colorize(values, valid, vmin, vmax):
    rgb = jet(values, vmin, vmax)
    rgb[~valid] = (40, 40, 40)
    return rgb


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "n/a"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    return ("%%.%dg" % digits) % x


def project(points, calib, width, height):
    """Sensor points -> (u, v, z) of those in front of the camera and inside the image."""
    p2 = calib["P2"].reshape(3, 4)
    tr = np.vstack([calib["Tr_velo_to_cam"][:12].reshape(3, 4), [0, 0, 0, 1]])
    cam = (tr @ np.c_[points[:, :3], np.ones(len(points))].T).T[:, :3]
    z = cam[:, 2]
    front = z > 0.1
    cam, z = cam[front], z[front]
    u = p2[0, 0] * cam[:, 0] / z + p2[0, 2]
    v = p2[1, 1] * cam[:, 1] / z + p2[1, 2]
    inside = (u >= 0) & (u < width) & (v >= 0) & (v < height)
    return u[inside], v[inside], z[inside]


# ---------------------------------------------------------------------------------------------


def ros_section(path, rel, metrics):
    """HTML of the ROS stage from demo_ros_summary.py's summary.json; adds rows to `metrics`."""
    if not path or not os.path.exists(path):
        return ("<h2>ROS pipeline</h2><p>not run (no %s: the ROS stage was skipped or failed)</p>" %
                html.escape(path or "summary.json"))
    with open(path) as f:
        summary = json.load(f)
    folder = os.path.dirname(os.path.abspath(path))
    frames = summary.get("input_frames") or 0
    scans = summary.get("input_scans")
    played = "%d images%s played" % (frames, "" if scans is None else ", %d %s scans" % (
        scans, summary.get("sensor", "")))
    rows = []
    for topic, t in summary.get("topics", {}).items():
        if not t.get("count") and topic in ("/conditioning/depth", "/diagnostics"):
            continue
        rows.append("<tr><td>%s</td><td>%d</td><td>%s</td></tr>" % (
            html.escape(topic), t.get("count", 0),
            "%.1f Hz" % t["rate_hz"] if t.get("rate_hz") else "n/a"))
    for topic in ("/depth/image", "/conditioning/image"):
        t = summary.get("topics", {}).get(topic, {})
        metrics.append(("ros", "%s messages (%s)" % (topic, played),
                        "%d" % t.get("count", 0),
                        "rate %s (header stamps, bag time)" %
                        ("%.1f Hz" % t["rate_hz"] if t.get("rate_hz") else "n/a")))
    ds = summary.get("depth_stats") or {}
    if ds:
        metrics.append(("ros", "depth nodelet compute (median / max)",
                        "%s / %s ms" % (fmt(ds.get("compute_ms_median")),
                                        fmt(ds.get("compute_ms_max"))),
                        "depth/stats; median points in view %s, kept pixels %s" %
                        (fmt(ds.get("points_in_view_median")), fmt(ds.get("kept_pixels_median")))))
    images = summary.get("images", {})
    cells = []
    d = images.get("depth")
    if d:
        cells.append('<figure><img src="%s"><figcaption>/depth/image at t = %.2f s (%dx%d, kept '
                     '%.0f %%)%s</figcaption></figure>' % (
                         rel(os.path.join(folder, d["png"])), d["stamp"], d["size"][1],
                         d["size"][0], 100 * d.get("kept_fraction", 0),
                         jet_css(d.get("vmin", 0), d.get("vmax", 1), "m")))
        if d.get("mask_png"):
            cells.append('<figure><img src="%s"><figcaption>/depth/mask (white: kept)'
                         '</figcaption></figure>' % rel(os.path.join(folder, d["mask_png"])))
    c = images.get("conditioning")
    if c:
        note = ""
        if c.get("coverage") is not None:
            note = ", rendered %.0f %%" % (100 * c["coverage"])
            metrics.append(("ros", "conditioning coverage (frame shown%s)" %
                            (", keyframe %.0f %%" % (100 * c["keyframe_coverage"])
                             if c.get("keyframe_coverage") is not None else ""),
                            "%.1f %%" % (100 * c["coverage"]), "/conditioning/mask == 255"))
        cells.append('<figure><img src="%s"><figcaption>/conditioning/image at t = %.2f s '
                     '(%dx%d%s): the first frame (keyframe) rendered into this pose'
                     '</figcaption></figure>' % (rel(os.path.join(folder, c["png"])), c["stamp"],
                                                 c["size"][1], c["size"][0], note))
        if c.get("mask_png"):
            cells.append('<figure><img src="%s"><figcaption>/conditioning/mask</figcaption>'
                         '</figure>' % rel(os.path.join(folder, c["mask_png"])))
    missing = summary.get("missing") or []
    warn = ("<p><b>No message on %s.</b></p>" % html.escape(", ".join(missing))) if missing else ""
    bag = summary.get("bag", "")
    return ('<h2>ROS pipeline (roslaunch multimodal_nvs demo.launch)</h2><p>The bag played with '
            'simulated time through both nodelets in one manager; outputs recorded to <a href="%s">'
            '%s</a>. Decoded from that bag:</p>%s<table><tr><th>topic</th><th>messages</th>'
            '<th>rate</th></tr>%s</table><div class="grid">%s</div>' %
            (rel(bag), html.escape(rel(bag)), warn, "".join(rows), "".join(cells)))


def rviz_section(folder, rel, metrics):
    """HTML of the rviz screenshot (scripts/rviz_screenshot.sh); adds its panel shares to
    `metrics`."""
    png = os.path.join(folder, "rviz.png") if folder else ""
    if not png or not os.path.exists(png):
        return ("<h2>rviz</h2><p>no screenshot (the rviz stage was skipped or failed; see "
                "logs/rviz.log)</p>")
    shares = []
    shares_txt = os.path.join(folder, "shares.txt")
    if os.path.exists(shares_txt):
        for line in open(shares_txt):
            if line.startswith("rviz panel "):
                name, value = line[len("rviz panel "):].split(": coloured share ")
                shares.append((name, value.split()[0]))
                metrics.append(("rviz", "coloured share of the %s panel" % name, value.split()[0], ""))
    listing = "".join("<li>%s: %s</li>" % (html.escape(n), html.escape(v)) for n, v in shares)
    return ('<h2>rviz (roslaunch multimodal_nvs demo.launch gui:=true)</h2><p>rviz/multimodal_nvs.rviz '
            'on a 1600x1000 virtual screen: the cloud coloured by its standard deviation (0..10 m), '
            'the camera image, depth/image_color (0..50 m) and depth/stddev_color (0..10 m). '
            'Coloured share of each image panel:</p><ul>%s</ul><img src="%s" '
            'style="max-width: 100%%">' % (listing, rel(png)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--frame", type=int, required=True)
    ap.add_argument("--frames", required=True)
    ap.add_argument("--sensor", default="radar")
    ap.add_argument("--depth-prefix", required=True)
    ap.add_argument("--conditioning", default="")
    ap.add_argument("--timings", default="")
    ap.add_argument("--title", default="multimodal_nvs demo")
    ap.add_argument("--bag", default="")
    ap.add_argument("--ros-summary", default="")
    ap.add_argument("--rviz", default="",
                    help="folder of scripts/rviz_screenshot.sh's rviz.png and shares.txt")
    args = ap.parse_args()

    out = os.path.abspath(args.out)
    rel = lambda p: os.path.relpath(p, out)  # noqa: E731
    pics = os.path.join(out, "report")
    os.makedirs(pics, exist_ok=True)
    fid = "%05d" % args.frame
    root = os.path.abspath(args.root)
    image_src = os.path.join(root, "lidar/training/image_2", fid + ".jpg")
    image_copy = os.path.join(pics, "input.jpg")
    shutil.copyfile(image_src, image_copy)
    width, height = jpeg_size(image_src)

    metrics = []  # (group, name, value, note)
    sections = []

    # Input image with the radar and LiDAR returns of the reference frame drawn over it.
    overlays = []
    for sensor, floats in (("radar", 7), ("lidar", 4)):
        bin_path = os.path.join(root, sensor, "training/velodyne", fid + ".bin")
        calib_path = os.path.join(root, sensor, "training/calib", fid + ".txt")
        if not (os.path.exists(bin_path) and os.path.exists(calib_path)):
            continue
        pts = np.fromfile(bin_path, dtype=np.float32).reshape(-1, floats)
        u, v, z = project(pts, read_calib(calib_path), width, height)
        metrics.append(("input", "%s returns (in image / total)" % sensor,
                        "%d / %d" % (len(u), len(pts)), "frame " + fid))
        if sensor == "lidar" and len(u) > 6000:  # keep the page light: every n-th point is drawn
            keep = np.linspace(0, len(u) - 1, 6000).astype(int)
            u, v, z = u[keep], v[keep], z[keep]
        overlays.append((sensor, len(pts), u, v, z))
    zmax = max([float(np.percentile(o[4], 95)) for o in overlays if len(o[4])] + [1.0])
    svg = []
    for sensor, _, u, v, z in overlays:
        radius = max(1.5, width / 320.0) if sensor == "radar" else max(0.8, width / 900.0)
        colours = jet(z, 0.0, zmax)
        svg.append('<g class="%s">' % sensor)
        for x, y, c in zip(u, v, colours):
            svg.append('<circle cx="%.1f" cy="%.1f" r="%.1f" fill="rgb(%d,%d,%d)"%s/>' %
                       (x, y, radius, c[0], c[1], c[2],
                        ' stroke="black" stroke-width="0.5"' if sensor == "radar" else ""))
        svg.append("</g>")
    toggles = " ".join('<label><input type="checkbox" checked onchange="document.querySelectorAll('
                       "'g.%s').forEach(g=>g.style.display=this.checked?'':'none')\"> %s</label>" %
                       (o[0], o[0]) for o in overlays)
    sections.append(
        '<h2>Input frame %s</h2><p>%s Colour = depth in the camera (0 to %.0f m).</p>'
        '<div class="overlay"><img src="%s" width="%d" height="%d">'
        '<svg viewBox="0 0 %d %d" width="%d" height="%d">%s</svg></div>%s' %
        (fid, toggles, zmax, rel(image_copy), width, height, width, height, width, height,
         "".join(svg), jet_css(0, zmax, "m")))

    # Depth completion outputs.
    prefix = os.path.abspath(args.depth_prefix)
    depth_npy = prefix + "_depth.npy"
    if os.path.exists(depth_npy):
        depth = np.load(depth_npy).astype(np.float64)
        variance = np.load(prefix + "_variance.npy").astype(np.float64)
        valid = np.load(prefix + "_valid.npy") != 0
        mask_png = os.path.join(pics, "mask.png")
        write_png(mask_png, np.where(valid, 255, 0).astype(np.uint8))
        kept = valid.mean()
        metrics.append(("depth", "kept pixels (retention)", "%.1f %%" % (100 * kept), ""))
        cells = []
        for name, suffix in (("depth", "_depth.png"), ("variance", "_variance.png")):
            if os.path.exists(prefix + suffix):
                cells.append('<figure><img src="%s"><figcaption>%s (%s, kept pixels; scale bar '
                             'in the image)</figcaption></figure>' % (rel(prefix + suffix), name,
                                                                     args.sensor))
        cells.append('<figure><img src="%s"><figcaption>mask: kept (white) after retention'
                     '</figcaption></figure>' % rel(mask_png))

        gt_path = os.path.join(root, "depth_gt", fid + ".npy")
        lidar_bin = os.path.join(root, "lidar/training/velodyne", fid + ".bin")
        lidar_calib = os.path.join(root, "lidar/training/calib", fid + ".txt")
        gt, gt_kind = None, ""
        if os.path.exists(gt_path):
            gt = np.load(gt_path).astype(np.float64)
            gt_kind = "dense ground truth (depth_gt)"
        elif os.path.exists(lidar_bin) and os.path.exists(lidar_calib) and args.sensor == "radar":
            pts = np.fromfile(lidar_bin, dtype=np.float32).reshape(-1, 4)
            u, v, z = project(pts, read_calib(lidar_calib), depth.shape[1], depth.shape[0])
            gt = np.zeros(depth.shape)
            order = np.argsort(-z)  # nearest point wins
            gt[v[order].astype(int), u[order].astype(int)] = z[order]
            gt_kind = "LiDAR points projected into the image (sparse)"
        if gt is not None and gt.shape == depth.shape:
            have = gt > 0
            # Pixels far from every sample keep (nearly) the prior variance, the largest one.
            informed = variance < 0.5 * np.nanmax(variance)
            # The depth file is masked (-1 where not kept), so "all predicted" differs from "kept"
            # only without retention, and "nearby" only where kept pixels lie far from samples:
            # a selection equal to an earlier one would only repeat its figures.
            shown = []
            for label, sel in (("kept pixels", have & valid),
                               ("kept pixels with samples nearby (variance < half the prior)",
                                have & valid & informed),
                               ("all predicted pixels", have & np.isfinite(depth) & (depth > 0))):
                if sel.sum() == 0 or any(np.array_equal(sel, earlier) for earlier in shown):
                    continue
                shown.append(sel)
                err = depth[sel] - gt[sel]
                metrics.append(("depth", "MAE vs GT, %s" % label, "%.3f m" % np.abs(err).mean(),
                                "%d px, %s" % (sel.sum(), gt_kind)))
                metrics.append(("depth", "RMSE vs GT, %s" % label,
                                "%.3f m" % np.sqrt((err ** 2).mean()),
                                "median |err| %.3f m" % np.median(np.abs(err))))
            if gt_kind.startswith("dense"):
                vmax = float(np.percentile(gt[have], 95))
                gt_png = os.path.join(pics, "depth_gt.png")
                write_png(gt_png, colorize(gt, have, 0.0, vmax))
                err_png = os.path.join(pics, "depth_error.png")
                err_map = np.abs(depth - gt)
                write_png(err_png, colorize(err_map, have & valid, 0.0, 5.0))
                cells.append('<figure><img src="%s"><figcaption>ground-truth depth (sky grey)%s'
                             '</figcaption></figure>' % (rel(gt_png), jet_css(0, vmax, "m")))
                cells.append('<figure><img src="%s"><figcaption>|depth - GT| on kept pixels%s'
                             '</figcaption></figure>' % (rel(err_png), jet_css(0, 5, "m")))
        else:
            metrics.append(("depth", "MAE / RMSE vs GT", "n/a",
                            "no depth_gt and no LiDAR scan for frame %s" % fid))
        sections.append('<h2>Depth completion (%s)</h2><div class="grid">%s</div>' %
                        (args.sensor, "".join(cells)))
    else:
        sections.append("<h2>Depth completion</h2><p>not run (no %s)</p>" % html.escape(depth_npy))

    # Conditioning frames, preview and the GEN3C export.
    cond = os.path.abspath(args.conditioning) if args.conditioning else ""
    if cond and os.path.isdir(cond):
        frames_dir = os.path.join(cond, "frames")
        names = sorted(os.listdir(frames_dir)) if os.path.isdir(frames_dir) else []
        cameras = {}
        if os.path.exists(os.path.join(cond, "cameras.json")):
            try:
                cameras = json.load(open(os.path.join(cond, "cameras.json")))
            except ValueError:
                cameras = {}
        recorded = cameras.get("recorded_frames") if isinstance(cameras, dict) else None
        if not recorded:
            recorded = list(range(0, len(names), max(1, len(names) // 8)))
        show = [i for i in recorded if i < len(names)][:16]
        cells = []
        for i in show:
            name = names[i]
            masks = os.path.join(cond, "masks", name)
            preview = os.path.join(cond, "preview", os.path.splitext(name)[0] + ".jpg")
            cell = '<figure><img src="%s"><figcaption>frame %d' % (
                rel(os.path.join(frames_dir, name)), i)
            if os.path.exists(preview):
                cell += ' &middot; <a href="%s">preview</a>' % rel(preview)
            if os.path.exists(masks):
                cell += ' &middot; <a href="%s">mask</a>' % rel(masks)
            cells.append(cell + "</figcaption></figure>")
        video = ""
        for candidate in ("preview.mp4", "preview.avi"):
            path = os.path.join(cond, candidate)
            if os.path.exists(path):
                video = ('<p><video controls loop src="%s" width="640"></video><br><a href="%s">'
                         '%s</a> (if the browser cannot play this codec, download it)</p>' %
                         (rel(path), rel(path), candidate))
                break
        gen3c = os.path.join(cond, "gen3c")
        listing = ""
        if os.path.isdir(gen3c):
            rows = []
            for name in sorted(os.listdir(gen3c)):
                path = os.path.join(gen3c, name)
                size = os.path.getsize(path) if os.path.isfile(path) else 0
                header = npy_shape(path) if name.endswith(".npy") else None
                shape = str(header.get("shape")) if isinstance(header, dict) else ""
                rows.append("<tr><td><a href='%s'>%s</a></td><td>%s</td><td>%.1f MB</td></tr>" %
                            (rel(path), html.escape(name), shape, size / 1e6))
            listing = ('<p>GEN3C input folder: <a href="%s/">%s/</a></p><table>%s</table>' %
                       (rel(gen3c), rel(gen3c), "".join(rows)))
        nvs = os.path.join(cond, "metrics.json")
        if os.path.exists(nvs):
            try:
                m = json.load(open(nvs))
                for block, note in (("mean", "all GT frames"),
                                    ("mean_without_reference", "GT frames except the input view")):
                    summary = m.get(block) if isinstance(m, dict) else None
                    if not isinstance(summary, dict):
                        continue
                    for key in ("psnr", "ssim", "covered_psnr", "coverage"):
                        if key in summary:
                            name = "%s (%s)" % (key.replace("_", " "), note)
                            metrics.append(("novel views", name, fmt(summary[key], 4),
                                            "conditioning renders vs recorded frames, "
                                            "the paper's metric protocol"))
            except ValueError:
                pass
        sections.append('<h2>Conditioning frames (recorded trajectory %s)</h2>%s<div class="grid">'
                        '%s</div>%s' % (html.escape(args.frames), video, "".join(cells), listing))
    else:
        sections.append("<h2>Conditioning frames</h2><p>not rendered (render_conditioning is not "
                        "part of this build, or the stage was skipped)</p>")

    # The ROS pipeline: the bag through both nodelets (launch/demo.launch), outputs recorded.
    sections.append(ros_section(args.ros_summary, rel, metrics))
    sections.append(rviz_section(args.rviz, rel, metrics))

    # Timings.
    timing_rows = ""
    if args.timings and os.path.exists(args.timings):
        for line in open(args.timings):
            parts = line.rstrip("\n").split("\t")
            if len(parts) == 3:
                timing_rows += "<tr><td>%s</td><td>%s s</td><td>%s</td></tr>" % tuple(
                    html.escape(p) for p in parts)

    metric_rows = "".join("<tr><td>%s</td><td>%s</td><td>%s</td><td>%s</td></tr>" %
                          tuple(html.escape(str(x)) for x in row) for row in metrics)
    bag = ('<p>ROS bag: <a href="%s">%s</a></p>' % (rel(args.bag), rel(args.bag))
           if args.bag and os.path.exists(args.bag) else "")
    page = """<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>%(title)s</title><style>
body { font-family: sans-serif; margin: 1.5em; max-width: 1400px; }
table { border-collapse: collapse; margin: 0.5em 0; }
td, th { border: 1px solid #ccc; padding: 3px 8px; }
.overlay { position: relative; display: inline-block; max-width: 100%%; }
.overlay img { display: block; max-width: 100%%; height: auto; }
.overlay svg { position: absolute; left: 0; top: 0; width: 100%%; height: 100%%; }
.grid { display: flex; flex-wrap: wrap; gap: 10px; }
.grid figure { margin: 0; max-width: 470px; } .grid img { max-width: 470px; }
.bar { display: flex; align-items: center; gap: 6px; font-size: 85%%; margin: 4px 0; }
.bar .grad { width: 240px; height: 12px; }
</style></head><body>
<h1>%(title)s</h1>
<p>Scene: %(root)s &middot; frames %(frames)s &middot; reference frame %(fid)s &middot;
sensor %(sensor)s</p>
%(bag)s
<h2>Metrics</h2><table><tr><th>group</th><th>metric</th><th>value</th><th>note</th></tr>
%(metrics)s</table>
%(sections)s
<h2>Stages</h2><table><tr><th>stage</th><th>time</th><th>status</th></tr>%(timings)s</table>
</body></html>
""" % dict(title=html.escape(args.title), root=html.escape(root), frames=html.escape(args.frames),
           fid=fid, sensor=html.escape(args.sensor), bag=bag, metrics=metric_rows,
           sections="\n".join(sections), timings=timing_rows)
    index = os.path.join(out, "index.html")
    with open(index, "w") as f:
        f.write(page)
    summary = {name: value for group, name, value, note in metrics
               if group in ("depth", "novel views", "ros")}
    print(json.dumps({"report": index, "metrics": summary}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
