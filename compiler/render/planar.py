"""What a side view of a planar multibody model draws, found from the flat model alone.

The renderer knows component *kinds*, not models: every instance whose type is a rigid bar, a
link, a body, a joint, a ground frame or a cylinder mount becomes a drawable part tied to the
frames whose `x`/`y` signals the simulation records; visual-only instances (`FlatSystem.visual`)
such as a BoxShape become fixed polygons; a soil-contact element becomes a tool whose frame leaves
a trail and whose payload is shown. Parts inside a link (its bars and body) are covered by the
link and are not drawn again.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from compiler.model.flat import FlatSystem

# Short type names (the last segment of the qualified component name) and the role they play.
LINK_TYPES = {"BodyShape"}
BAR_TYPES = {"FixedTranslation"}
BODY_TYPES = {"Body"}
JOINT_TYPES = {"Revolute"}
GROUND_TYPES = {"World", "Fixed"}
CYLINDER_TYPES = {"PlanarCylinderMount"}
BOX_TYPES = {"BoxShape"}
TOOL_CONTACT_TYPES = {"SoilContact"}


@dataclass(frozen=True)
class Segment:
    """A rigid bar drawn from one frame to another; a link also marks its centre of mass."""
    path: str
    start: str
    end: str
    center_of_mass: str | None = None


@dataclass(frozen=True)
class Marker:
    """A point drawn at a frame: a joint, a ground anchor or a free body."""
    path: str
    frame: str


@dataclass(frozen=True)
class Cylinder:
    """A line actuator between a barrel anchor and a rod anchor."""
    path: str
    base: str
    rod: str
    retracted_length: float
    stroke: float


@dataclass(frozen=True)
class Box:
    """A visual-only box projected on the x-y plane (a convex polygon in world coordinates)."""
    path: str
    polygon: tuple[tuple[float, float], ...]
    color: tuple[float, float, float, float]


@dataclass(frozen=True)
class ToolContact:
    """A tool frame in contact with a medium: its path is traced and its payload shown."""
    path: str
    frame: str
    payload: str
    capacity: float | None


@dataclass
class PlanarScene:
    links: list[Segment] = field(default_factory=list)
    bars: list[Segment] = field(default_factory=list)
    bodies: list[Marker] = field(default_factory=list)
    joints: list[Marker] = field(default_factory=list)
    grounds: list[Marker] = field(default_factory=list)
    cylinders: list[Cylinder] = field(default_factory=list)
    boxes: list[Box] = field(default_factory=list)
    tools: list[ToolContact] = field(default_factory=list)

    def is_empty(self) -> bool:
        return not (self.links or self.bars or self.bodies or self.joints or self.cylinders
                    or self.boxes or self.tools)

    def frames(self) -> list[str]:
        """Every frame whose position the drawing needs, in a stable order."""
        found: list[str] = []
        for segment in self.links + self.bars:
            found += [segment.start, segment.end]
            if segment.center_of_mass:
                found.append(segment.center_of_mass)
        for marker in self.bodies + self.joints + self.grounds:
            found.append(marker.frame)
        for cylinder in self.cylinders:
            found += [cylinder.base, cylinder.rod]
        for tool in self.tools:
            found.append(tool.frame)
        return list(dict.fromkeys(found))

    def summary(self) -> dict[str, int]:
        return {"links": len(self.links), "bars": len(self.bars), "bodies": len(self.bodies),
                "joints": len(self.joints), "grounds": len(self.grounds),
                "cylinders": len(self.cylinders), "boxes": len(self.boxes), "tools": len(self.tools)}


def short_type(qualified: str) -> str:
    return qualified.rsplit(".", 1)[-1]


def instance_types(flat: FlatSystem) -> dict[str, str]:
    """Instance path -> short component type, for every instance of the model tree."""
    components = flat.metadata.get("components", {})
    return {path: short_type(info.get("type", "")) for path, info in components.items() if path}


def discover(flat: FlatSystem) -> PlanarScene:
    types = instance_types(flat)
    parameters = flat.parameter_values()
    links = [path for path, kind in types.items() if kind in LINK_TYPES]
    scene = PlanarScene()
    for path, kind in types.items():
        if _inside_any(path, links):
            continue
        if kind in LINK_TYPES:
            body = f"{path}.body"
            center = f"{body}.frame_a" if types.get(body) in BODY_TYPES else None
            scene.links.append(Segment(path, f"{path}.frame_a", f"{path}.frame_b", center))
        elif kind in BAR_TYPES:
            scene.bars.append(Segment(path, f"{path}.frame_a", f"{path}.frame_b"))
        elif kind in BODY_TYPES:
            scene.bodies.append(Marker(path, f"{path}.frame_a"))
        elif kind in JOINT_TYPES:
            scene.joints.append(Marker(path, f"{path}.frame_a"))
        elif kind in GROUND_TYPES:
            scene.grounds.append(Marker(path, f"{path}.frame_b"))
        elif kind in CYLINDER_TYPES:
            scene.cylinders.append(Cylinder(path, f"{path}.frame_a", f"{path}.frame_b",
                                            parameters.get(f"{path}.s_offset", 0.0),
                                            parameters.get(f"{path}.stroke", 0.0)))
        elif kind in TOOL_CONTACT_TYPES:
            scene.tools.append(ToolContact(path, f"{path}.frame_a", f"{path}.m_load",
                                           parameters.get(f"{path}.m_capacity")))
    for path, info in flat.visual.items():
        if short_type(info.get("type", "")) in BOX_TYPES and _renders(info.get("parameters", {})):
            scene.boxes.append(box_from_parameters(path, info["parameters"]))
    return scene


def _inside_any(path: str, parents: list[str]) -> bool:
    return any(path.startswith(parent + ".") for parent in parents)


def _renders(parameters: dict) -> bool:
    return bool(parameters.get("render", True))


def box_from_parameters(path: str, parameters: dict) -> Box:
    """Corners of the BoxShape (start at r, `length` along length_direction, centred across it in
    width and height), projected on the x-y plane and wrapped in their convex hull."""
    start = np.asarray(parameters.get("r", [0, 0, 0]), dtype=float)
    along = _unit(parameters.get("length_direction", [1, 0, 0]))
    across = np.asarray(parameters.get("width_direction", [0, 1, 0]), dtype=float)
    across = _unit(across - across.dot(along) * along)
    normal = np.cross(along, across)
    length = float(parameters.get("length", 1.0))
    width = float(parameters.get("width", 0.1))
    height = float(parameters.get("height", 0.1))
    corners = [start + a * length * along + b * width * across + c * height * normal
               for a in (0.0, 1.0) for b in (-0.5, 0.5) for c in (-0.5, 0.5)]
    polygon = convex_hull([(float(p[0]), float(p[1])) for p in corners])
    color = tuple(float(v) for v in parameters.get("color", [0.5, 0.5, 0.5, 1.0]))
    return Box(path, tuple(polygon), (color + (1.0,) * 4)[:4])


def _unit(vector) -> np.ndarray:
    v = np.asarray(vector, dtype=float)
    norm = np.linalg.norm(v)
    return v / norm if norm > 0 else v


def convex_hull(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """Counter-clockwise hull (Andrew's monotone chain); collinear and repeated points dropped."""
    pts = sorted(set((round(x, 12), round(y, 12)) for x, y in points))
    if len(pts) <= 2:
        return pts

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


class FrameTracks:
    """Positions of the scene's frames over time, interpolated from a Result at any times."""

    def __init__(self, result, frames: list[str]):
        self.time = np.asarray(result.time, dtype=float)
        self._xy: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.missing: list[str] = []
        for frame in frames:
            x_name, y_name = f"{frame}.x", f"{frame}.y"
            if x_name in result and y_name in result:
                self._xy[frame] = (np.asarray(result[x_name]), np.asarray(result[y_name]))
            else:
                self.missing.append(frame)

    def has(self, frame: str | None) -> bool:
        return frame is not None and frame in self._xy

    def at(self, frame: str, times: np.ndarray) -> np.ndarray:
        """(len(times), 2) positions."""
        x, y = self._xy[frame]
        return np.column_stack([np.interp(times, self.time, x), np.interp(times, self.time, y)])

    def all_points(self) -> np.ndarray:
        if not self._xy:
            return np.zeros((0, 2))
        return np.vstack([np.column_stack(xy) for xy in self._xy.values()])

    def coincide(self, first: str, second: str, tolerance: float = 1e-9) -> bool:
        """True when two frames are at the same place all the time (they are connected)."""
        if not (self.has(first) and self.has(second)):
            return False
        (x1, y1), (x2, y2) = self._xy[first], self._xy[second]
        scale = 1.0 + max(np.max(np.abs(x1)), np.max(np.abs(y1)))
        return bool(np.max(np.hypot(x1 - x2, y1 - y2)) <= tolerance * scale)


def drawable(scene: PlanarScene, tracks: FrameTracks) -> PlanarScene:
    """The scene without the parts whose frames the result does not record."""
    def ok(*frames):
        return all(tracks.has(f) for f in frames if f is not None)

    return PlanarScene(
        links=[s for s in scene.links if ok(s.start, s.end)],
        bars=[s for s in scene.bars if ok(s.start, s.end)],
        bodies=[m for m in scene.bodies if ok(m.frame)],
        joints=[m for m in scene.joints if ok(m.frame)],
        grounds=[m for m in scene.grounds if ok(m.frame)],
        cylinders=[c for c in scene.cylinders if ok(c.base, c.rod)],
        boxes=list(scene.boxes),
        tools=[t for t in scene.tools if ok(t.frame)],
    )


def carrier_of(tool: ToolContact, scene: PlanarScene, tracks: FrameTracks) -> Segment | None:
    """The link whose end the tool frame is attached to (found by the frames coinciding)."""
    for link in scene.links:
        if tracks.coincide(link.end, tool.frame) or tracks.coincide(link.start, tool.frame):
            return link
    return None
