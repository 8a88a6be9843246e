"""The task-motion GIF as a report page with play/pause and a slider over its frames.

The Snakemake report shows no GIF itself, and a browser cannot pause or scrub one; WebCodecs'
``ImageDecoder`` could, but the single-file report shows a page as a ``data:`` URL, which is no
secure context, and there the decoder is missing. So the page carries the GIF's frames as
changes: the frames are cut into square tiles of :data:`TILE_PX` pixels, every distinct tile is
stored once in one PNG (the atlas), and each frame lists the tiles that changed since the
previous frame (the first frame lists them all). A few lines of JavaScript draw a frame into a
canvas by replaying the changes from the first frame. The page is about the GIF's size, well
under the 2 MiB ``data:`` URL the single-file report can show
(:data:`qsm.report.plotly_page.CHROMIUM_MAX_URL_CHARS`).
"""

from __future__ import annotations

import base64
import html
import io
import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from PIL import Image, ImageSequence

#: Side of a tile (px).
TILE_PX = 16
#: Tiles per row of the atlas.
ATLAS_COLUMNS = 64

_PLAYER = """
(async () => {
  const data = JSON.parse(document.getElementById("motion-data").textContent);
  const canvas = document.getElementById("motion-canvas");
  const slider = document.getElementById("motion-slider");
  const button = document.getElementById("motion-play");
  const label = document.getElementById("motion-frame");
  const atlas = new Image();
  atlas.src = data.atlas;
  await atlas.decode();
  const ctx = canvas.getContext("2d");
  const n = data.frames.length, T = data.tile, columns = data.columns;
  slider.max = n - 1;
  let frame = 0, drawn = -1, timer = null;
  const show = (k) => {
    if (k < drawn) drawn = -1;  // replay from the first frame
    for (let j = drawn + 1; j <= k; j++) {
      for (const [slot, x, y] of data.frames[j]) {
        const sx = (slot % columns) * T, sy = Math.floor(slot / columns) * T;
        ctx.drawImage(atlas, sx, sy, T, T, x, y, T, T);
      }
    }
    drawn = frame = k;
    slider.value = k;
    label.textContent = `frame ${k + 1} of ${n}`;
  };
  const pause = () => { clearInterval(timer); timer = null; button.textContent = "play"; };
  const play = () => {
    if (frame === n - 1) show(0);
    timer = setInterval(() => (frame < n - 1 ? show(frame + 1) : pause()), data.frame_ms);
    button.textContent = "pause";
  };
  button.onclick = () => (timer ? pause() : play());
  slider.oninput = () => { pause(); show(Number(slider.value)); };
  show(0);
  play();
})();
"""


def gif_frames(gif: str | Path) -> list[NDArray]:
    """Every frame of ``gif`` as an RGB array (rows, columns, 3)."""
    with Image.open(gif) as im:
        return [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(im)]


def tile_changes(frames: Sequence[NDArray]) -> tuple[NDArray, list[list[list[int]]]]:
    """The distinct :data:`TILE_PX` tiles of ``frames`` (slots, TILE_PX, TILE_PX, 3) and, for each
    frame, ``[slot, left px, top px]`` of every tile that differs from the previous frame's (of
    every tile for the first frame). Frames are padded white to whole tiles."""
    h, w = frames[0].shape[:2]
    rows, cols = -(-h // TILE_PX), -(-w // TILE_PX)
    slots: dict[bytes, int] = {}
    tiles: list[NDArray] = []
    changes: list[list[list[int]]] = []
    previous = None
    for rgb in frames:
        padded = np.full((rows * TILE_PX, cols * TILE_PX, 3), 255, np.uint8)
        padded[:h, :w] = rgb
        blocks = padded.reshape(rows, TILE_PX, cols, TILE_PX, 3).swapaxes(1, 2)
        changed = (
            np.ones((rows, cols), bool)
            if previous is None
            else np.any(blocks != previous, axis=(2, 3, 4))
        )
        entries = []
        for r, c in zip(*np.nonzero(changed), strict=True):
            key = blocks[r, c].tobytes()
            if key not in slots:
                slots[key] = len(tiles)
                tiles.append(blocks[r, c])
            entries.append([slots[key], int(c) * TILE_PX, int(r) * TILE_PX])
        changes.append(entries)
        previous = blocks
    return np.stack(tiles), changes


def atlas_png(tiles: NDArray) -> bytes:
    """The tiles in rows of :data:`ATLAS_COLUMNS` as one PNG (a palette PNG when they have at most
    256 colours, as a GIF's frames do)."""
    n = len(tiles)
    rows = -(-n // ATLAS_COLUMNS)
    grid = np.full((rows * ATLAS_COLUMNS, TILE_PX, TILE_PX, 3), 255, np.uint8)
    grid[:n] = tiles
    atlas = grid.reshape(rows, ATLAS_COLUMNS, TILE_PX, TILE_PX, 3).swapaxes(1, 2)
    atlas = atlas.reshape(rows * TILE_PX, ATLAS_COLUMNS * TILE_PX, 3)
    packed = atlas.astype(np.uint32) @ np.array([1 << 16, 1 << 8, 1], np.uint32)
    colours, index = np.unique(packed, return_inverse=True)
    if len(colours) <= 256:
        image = Image.fromarray(index.reshape(atlas.shape[:2]).astype(np.uint8), "P")
        rgb = (colours[:, None] >> np.array([16, 8, 0], np.uint32)) & 0xFF
        image.putpalette(rgb.astype(np.uint8).tobytes())
    else:
        image = Image.fromarray(atlas, "RGB")
    buffer = io.BytesIO()
    image.save(buffer, "PNG", optimize=True)
    return buffer.getvalue()


def write_viewer_html(
    gif: str | Path, path: str | Path, title: str, lines: Sequence[str], fps: float = 10.0
) -> Path:
    """Write the page playing ``gif`` (frames ``1 / fps`` s apart) under ``title`` with ``lines``
    of text (see the module docstring); return its path."""
    frames = gif_frames(gif)
    tiles, changes = tile_changes(frames)
    data = {
        "atlas": "data:image/png;base64," + base64.b64encode(atlas_png(tiles)).decode(),
        "tile": TILE_PX,
        "columns": ATLAS_COLUMNS,
        "frame_ms": 1000.0 / fps,
        "frames": changes,
    }
    h, w = frames[0].shape[:2]
    items = "".join(f"<li>{html.escape(line)}</li>" for line in lines)
    out = Path(path)
    out.write_text(
        "<!doctype html>\n<html><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title></head>\n"
        "<body style='font-family: sans-serif; margin: 12px'>\n"
        f"<h3>{html.escape(title)}</h3>\n"
        f"<canvas id='motion-canvas' width='{w}' height='{h}'></canvas><br>\n"
        "<button id='motion-play' style='width: 5em'>pause</button>\n"
        f"<input id='motion-slider' type='range' min='0' value='0' style='width: {w - 160}px'>\n"
        "<span id='motion-frame'></span>\n"
        f"<ul style='font-size: 13px'>{items}</ul>\n"
        f"<script type='application/json' id='motion-data'>{json.dumps(data)}</script>\n"
        f"<script>{_PLAYER}</script>\n</body></html>\n"
    )
    return out
