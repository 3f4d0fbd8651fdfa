"""Side-view GIF or MP4 of a planar multibody simulation, drawn from the parts `planar.discover`
finds. The figure is a bare matplotlib Figure on its own Agg canvas: pyplot is never imported, so
the user's matplotlib backend is left as it was."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from compiler.model.balance import span_from_text
from compiler.errors import DyadError
from compiler.render import planar, video
from compiler.runtime.writers import atomic_write

LINK_COLOR = "#f2a900"
LINK_EDGE = "#5a4300"
BAR_COLOR = "#6b6b6b"
BARREL_COLOR = "#3a3a3a"
ROD_COLOR = "#8c8c8c"
TRAIL_COLOR = "#d62728"
DEFAULT_PAYLOAD_COLOR = (0.47, 0.35, 0.2, 1.0)
# The barrel covers this share of the anchor distance at zero extension; the rest is visible rod.
BARREL_SHARE_OF_RETRACTED = 0.75
# The largest payload disc (at capacity) has this radius relative to the carrying link's length.
PAYLOAD_RADIUS_SHARE = 0.4


@dataclass
class _Payload:
    tool: planar.ToolContact
    anchor: str                  # frame the disc is centred on
    max_radius: float
    mass: np.ndarray             # payload on the result's time grid
    capacity: float
    color: tuple


def model_title(flat) -> str:
    return planar.short_type(flat.name or "model")


def nothing_to_draw(flat, detail: str) -> DyadError:
    return DyadError(f"nothing to draw: {detail}", span_from_text(flat.metadata.get("model_span")),
                     hint="the side view draws planar multibody parts (BodyShape, FixedTranslation, Body, "
                          "Revolute, PlanarCylinderMount, SoilContact) and visual BoxShapes")


def prepare(flat, result) -> tuple[planar.PlanarScene, planar.FrameTracks]:
    """The drawable scene of a model with the recorded frame tracks; a DyadError when empty."""
    found = planar.discover(flat)
    if found.is_empty():
        raise nothing_to_draw(flat, f"{model_title(flat)} has no planar multibody parts")
    tracks = planar.FrameTracks(result, found.frames())
    scene = planar.drawable(found, tracks)
    if scene.is_empty():
        raise nothing_to_draw(flat, f"the result of {model_title(flat)} records none of the frame positions "
                                    f"of its parts (missing e.g. {tracks.missing[0]}.x)")
    return scene, tracks


def animate(compilation, result, path, *, fps: int = 12, frames: int = 120, dpi: int = 100,
            video_format: str | None = None) -> dict:
    """Write a GIF or MP4 (`video_format`, default from the extension of `path`) of `result`,
    frames evenly spaced over its time span, to `path`, atomically.

    `compilation` is an api.Compilation or a FlatSystem. Returns what was drawn (part counts,
    frame count)."""
    flat = getattr(compilation, "flat", compilation)
    chosen = video.format_of(path, video_format)
    video.check_rate(fps, frames)
    if chosen == "mp4":
        video.ffmpeg()
    scene, tracks = prepare(flat, result)
    times = np.linspace(float(result.time[0]), float(result.time[-1]), frames)
    fig, draw_frame, moving = _build_figure(flat, scene, tracks, result)
    render = _frame_renderer(fig, draw_frame, moving, dpi)
    atomic_write(path, lambda temp_path: video.write_video(temp_path, chosen, render, times, fps))
    return {"frames": frames, "fps": fps, **scene.summary()}


def _frame_renderer(fig, draw_frame, moving: list, dpi: int):
    """A function from times to one RGB image per time. The static part (axes, ticks, boxes) is
    drawn once and restored for every frame; only the moving artists are redrawn on top
    (blitting), which keeps a 120-frame scene at a few seconds instead of redrawing every tick
    label each frame."""
    from PIL import Image

    fig.set_dpi(dpi)
    canvas = fig.canvas
    for artist in moving:
        artist.set_animated(True)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)
    in_order = sorted(moving, key=lambda artist: artist.get_zorder())
    size = canvas.get_width_height()

    def render(times):
        for t in times:
            canvas.restore_region(background)
            draw_frame(float(t))
            for artist in in_order:
                artist.axes.draw_artist(artist)
            yield (Image.frombuffer("RGBA", size, bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
                   .convert("RGB"))
    return render


def _build_figure(flat, scene: planar.PlanarScene, tracks: planar.FrameTracks, result):
    """The figure, the function that moves its artists to a time, and the moving artists."""
    from matplotlib.patches import Polygon

    fig, ax = _axes(flat, scene, tracks)
    for box in scene.boxes:
        ax.add_patch(Polygon(box.polygon, closed=True, facecolor=box.color, edgecolor="none", zorder=0))
    for ground in scene.grounds:
        x0, y0 = tracks.at(ground.frame, np.array([result.time[0]]))[0]
        ax.plot([x0], [y0], marker="^", markersize=14, color="#222222", zorder=1)
    artists = _moving_artists(ax, scene, tracks, result)
    fig.tight_layout()
    moving = [artist for group in (artists.bars, artists.rods, artists.barrels, artists.link_edges,
                                   artists.links, artists.centers, artists.bodies, artists.joints,
                                   artists.trails)
              for _, artist in group]
    moving += [disc for _, disc in artists.payloads] + [artists.label]
    return fig, lambda t: _draw_frame(artists, tracks, t), moving


def _axes(flat, scene: planar.PlanarScene, tracks: planar.FrameTracks):
    """A figure on its own Agg canvas sized to the scene's extent, and its labelled axes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    (x_lo, x_hi), (y_lo, y_hi) = _limits(scene, tracks)
    width = 8.0
    height = min(max(width * (y_hi - y_lo) / (x_hi - x_lo), 3.0), 9.0)
    fig = Figure(figsize=(width, height))
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(y_lo, y_hi)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(model_title(flat))
    ax.grid(True, alpha=0.25)
    return fig, ax


@dataclass
class _Artists:
    """The artists a frame moves, each paired with the part it draws."""
    bars: list
    link_edges: list
    links: list
    centers: list
    rods: list
    barrels: list
    bodies: list
    joints: list
    trails: list
    payloads: list
    label: object


def _moving_artists(ax, scene: planar.PlanarScene, tracks: planar.FrameTracks, result) -> _Artists:
    from matplotlib.patches import Circle

    def line(**style):
        return ax.plot([], [], solid_capstyle="round", **style)[0]

    def dots(parts, **style):
        return [(part, ax.plot([], [], "o", **style)[0]) for part in parts]

    payloads = []
    for tool in scene.tools:
        payload = _payload(tool, scene, tracks, result)
        if payload is not None:
            disc = Circle((0, 0), 0.0, facecolor=payload.color, edgecolor="black", lw=0.8, zorder=7)
            ax.add_patch(disc)
            payloads.append((payload, disc))
    return _Artists(
        bars=[(s, line(color=BAR_COLOR, lw=3, zorder=2)) for s in scene.bars],
        # Cylinders sit beside the links in the real machine; drawn over them they stay visible.
        link_edges=[(s, line(color=LINK_EDGE, lw=10, zorder=3)) for s in scene.links],
        links=[(s, line(color=LINK_COLOR, lw=7, zorder=3.1)) for s in scene.links],
        centers=dots([s for s in scene.links if tracks.has(s.center_of_mass)], color=LINK_EDGE,
                     markersize=4, zorder=3.2),
        rods=[(c, line(color=ROD_COLOR, lw=3.5, zorder=4)) for c in scene.cylinders],
        barrels=[(c, line(color=BARREL_COLOR, lw=8, zorder=4.1)) for c in scene.cylinders],
        bodies=dots(scene.bodies, color="black", markersize=9, zorder=6),
        joints=dots(scene.joints, markerfacecolor="white", markeredgecolor="black", markersize=7, zorder=8),
        trails=[(t, line(color=TRAIL_COLOR, lw=1.2, ls="--", zorder=1.5)) for t in scene.tools],
        payloads=payloads,
        label=ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", ha="left", family="monospace",
                      bbox={"facecolor": "white", "alpha": 0.8, "edgecolor": "none"}, zorder=10))


def _draw_frame(artists: _Artists, tracks: planar.FrameTracks, t: float) -> None:
    """Every moving artist placed where its part is at time `t`."""
    when = np.array([t])
    for segments in (artists.bars, artists.link_edges, artists.links):
        for segment, artist in segments:
            a, b = tracks.at(segment.start, when)[0], tracks.at(segment.end, when)[0]
            artist.set_data([a[0], b[0]], [a[1], b[1]])
    for segment, artist in artists.centers:
        c = tracks.at(segment.center_of_mass, when)[0]
        artist.set_data([c[0]], [c[1]])
    for markers in (artists.bodies, artists.joints):
        for marker, artist in markers:
            p = tracks.at(marker.frame, when)[0]
            artist.set_data([p[0]], [p[1]])
    for (cylinder, rod), (_, barrel) in zip(artists.rods, artists.barrels):
        base, tip = tracks.at(cylinder.base, when)[0], tracks.at(cylinder.rod, when)[0]
        barrel_start, barrel_end, rod_start = cylinder_geometry(base, tip, cylinder.retracted_length)
        barrel.set_data([barrel_start[0], barrel_end[0]], [barrel_start[1], barrel_end[1]])
        rod.set_data([rod_start[0], tip[0]], [rod_start[1], tip[1]])
    for tool, artist in artists.trails:
        past = np.append(tracks.time[tracks.time < t], t)
        path = tracks.at(tool.frame, past)
        artist.set_data(path[:, 0], path[:, 1])
    text = [f"t = {t:6.2f} s"]
    for payload, disc in artists.payloads:
        mass = float(np.interp(t, tracks.time, payload.mass))
        disc.center = tuple(tracks.at(payload.anchor, when)[0])
        disc.set_radius(payload.max_radius * np.sqrt(max(mass, 0.0) / payload.capacity))
        text.append(f"payload {mass:6.1f} kg")
    artists.label.set_text("\n".join(text))


def cylinder_geometry(base: np.ndarray, tip: np.ndarray, retracted_length: float):
    """Barrel from the base anchor towards the rod anchor, and where the visible rod starts (the rod
    runs on inside the barrel, so it starts halfway along it)."""
    distance = float(np.hypot(*(tip - base)))
    if distance == 0.0:
        return base, base, base
    direction = (tip - base) / distance
    barrel = BARREL_SHARE_OF_RETRACTED * retracted_length if retracted_length > 0 else 0.5 * distance
    barrel = min(barrel, distance)
    return base, base + barrel * direction, base + 0.5 * barrel * direction


def _payload(tool: planar.ToolContact, scene, tracks, result) -> _Payload | None:
    if tool.payload not in result:
        return None
    mass = np.asarray(result[tool.payload], dtype=float)
    capacity = tool.capacity if tool.capacity and tool.capacity > 0 else float(np.max(np.abs(mass)))
    if capacity <= 0:
        capacity = 1.0
    carrier = planar.carrier_of(tool, scene, tracks)
    anchor, size = tool.frame, 0.5
    if carrier is not None:
        anchor = carrier.center_of_mass if tracks.has(carrier.center_of_mass) else tool.frame
        start = tracks.at(carrier.start, tracks.time[:1])[0]
        end = tracks.at(carrier.end, tracks.time[:1])[0]
        size = float(np.hypot(*(end - start))) or size
    own_boxes = [b for b in scene.boxes if b.path.startswith(tool.path + ".")]
    color = own_boxes[0].color if own_boxes else DEFAULT_PAYLOAD_COLOR
    return _Payload(tool, anchor, PAYLOAD_RADIUS_SHARE * size, mass, capacity, color)


def _limits(scene: planar.PlanarScene, tracks: planar.FrameTracks):
    points = [tracks.all_points()] + [np.asarray(b.polygon) for b in scene.boxes]
    cloud = np.vstack([p for p in points if len(p)])
    lo, hi = cloud.min(axis=0), cloud.max(axis=0)
    span = max(float(np.max(hi - lo)), 1e-3)
    pad = 0.08 * span
    return (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)
