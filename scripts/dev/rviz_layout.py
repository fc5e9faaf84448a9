#!/usr/bin/python3
"""Prints the "QMainWindow State" of rviz/multimodal_nvs.rviz: where rviz docks its panels.

rviz restores its dock layout with QMainWindow::restoreState from this hex string, which normally
only rviz itself writes (File > Save Config). Written here from the layout below so that it can be
read and changed: Qt 5's format (QMainWindow::saveState: version marker, version, then
QDockAreaLayout::saveState; no toolbar state, which restoreState then leaves as it is).

  left dock: Displays; Views, Time and the disabled image displays' docks hidden
  right dock: the camera image, the colour-mapped depth and standard deviation, the conditioning
              image, stacked; the 3D view takes the rest of the 1600x1000 window.

Usage: scripts/dev/rviz_layout.py  (paste the line into Window Geometry: QMainWindow State)
"""
import struct

DOCK_STATE, SEQUENCE, WIDGET = 0xFD, 0xFC, 0xFB
LEFT, RIGHT = 0, 1
VERTICAL = 2  # Qt::Vertical
VISIBLE = 1
TOP_AREA, BOTTOM_AREA = 4, 8  # Qt::DockWidgetArea of the four corners
SEPARATOR = 6  # pixels between stacked docks (Qt recomputes it; only the shares matter)

WINDOW = (1600, 1000)
DOCK_HEIGHT = 900
LEFT_WIDTH = 300
RIGHT_WIDTH = 500
RIGHT_PANELS = ["Camera image", "Depth (0..50 m)", "Std. deviation (0..10 m)",
                "Conditioning image"]
# Hidden docks too: rviz enables an image display whose dock is shown, so the disabled ones are
# listed here as hidden.
LEFT_PANELS = [("Displays", True), ("Views", False), ("Time", False),
               ("Mask (kept = white)", False), ("Conditioning mask", False)]


def qstring(text):
    data = text.encode("utf-16-be")
    return struct.pack(">I", len(data)) + data


def sequence(panels, extent):
    """A vertical sequence of (name, visible) docks sharing `extent` pixels equally."""
    shown = [p for p in panels if p[1]]
    size = (extent - SEPARATOR * (len(shown) - 1)) // max(1, len(shown))
    out = struct.pack(">BBi", SEQUENCE, VERTICAL, len(panels))
    pos = 0
    for name, visible in panels:
        out += struct.pack(">B", WIDGET) + qstring(name) + struct.pack(">B", VISIBLE if visible else 0)
        out += struct.pack(">iiii", pos, size if visible else 0, 0, 0)
        if visible:
            pos += size + SEPARATOR
    return out


def main():
    state = struct.pack(">ii", 0xFF, 0)  # QMainWindowLayout::VersionMarker, version 0
    state += struct.pack(">Bi", DOCK_STATE, 2)
    state += struct.pack(">iii", LEFT, LEFT_WIDTH, DOCK_HEIGHT) + sequence(LEFT_PANELS, DOCK_HEIGHT)
    state += struct.pack(">iii", RIGHT, RIGHT_WIDTH, DOCK_HEIGHT)
    state += sequence([(name, True) for name in RIGHT_PANELS], DOCK_HEIGHT)
    state += struct.pack(">ii", WINDOW[0] - RIGHT_WIDTH, DOCK_HEIGHT)  # central widget
    state += struct.pack(">iiii", TOP_AREA, TOP_AREA, BOTTOM_AREA, BOTTOM_AREA)
    print(state.hex())


if __name__ == "__main__":
    main()
