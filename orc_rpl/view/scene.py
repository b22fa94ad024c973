"""The view's scene: the cell's geoms, the world's objects and frames, positions, planned paths and the TCP trace in viser."""

from __future__ import annotations

from typing import Any

import numpy as np
import viser
import viser.transforms as tf

from orc_rpl.plant.shapes import Frames, Poses, Shape
from orc_rpl.view.framing import Framing

#: Colours (RGB 0..255) of what the view draws over the cell.
PATH_RGB = (255, 140, 0)
TRACE_RGB = (220, 30, 60)
POSITION_AXES_M = 0.06
OBJECT_AXES_M = 0.1
#: The TCP trace is drawn in chunks of this many points: only the newest chunk is sent again as it grows.
TRACE_CHUNK = 200
#: Planned paths kept on screen (the oldest one's node shows the next).
PATHS_KEPT = 40
#: What is selected (a position picked at the pendant, the motion at the program pointer) is drawn this much larger.
HIGHLIGHT_SCALE = 2.5
HIGHLIGHT_RGB = (30, 120, 255)
#: The node that carries what is mounted on the robot's flange (tools), moved by `show`.
FLANGE_NODE = "/flange"
#: Spot welds: a small ball where the gun closed, green when good and red when not.
WELD_RADIUS_M = 0.008
GOOD_RGB = (40, 170, 60)
BAD_RGB = (220, 30, 30)
#: The light from the sky and the ground that replaces the environment map: it keeps the cell looking as it did.
FILL_GROUND_RGB = (120, 120, 120)
FILL_INTENSITY = 1.5


def wxyz_of(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a rotation matrix."""
    return tf.SO3.from_matrix(np.asarray(rotation, dtype=float)).wxyz


def wxyz_of_many(rotations: np.ndarray) -> np.ndarray:
    """The unit quaternions (n, 4) of rotation matrices (n, 3, 3), in one vectorised call."""
    return tf.SO3.from_matrix(np.asarray(rotations, dtype=float)).wxyz


def _rgb(rgba: tuple[float, ...]) -> tuple[int, int, int]:
    return (int(round(255 * rgba[0])), int(round(255 * rgba[1])), int(round(255 * rgba[2])))


class CellScene:
    """What one viser server shows; the handles stay readable so tests and the pendant can ask what is drawn."""

    def __init__(self, server: viser.ViserServer, shadows: bool = False, environment_map: bool = False) -> None:
        self.server = server
        self.scene = server.scene
        self.moving: dict[int, Any] = {}          #: geom index -> node of a geom that moves with a body
        self.shapes: dict[str, Any] = {}          #: geom name -> node, every geom of the cell
        self.objects: dict[str, Any] = {}         #: world object name -> its frame node
        self.positions: dict[str, Any] = {}       #: position name -> its small frame
        self.paths: dict[int, Any] = {}           #: move id -> the planned path's line segments
        self._path_nodes = 0                      #: line-segment nodes made for paths (at most PATHS_KEPT)
        self.trace_m: list[np.ndarray] = []       #: TCP trace points so far, world, m
        self._trace_nodes: list[Any] = []
        self.welds: dict[int, Any] = {}           #: weld number -> its spot
        self.process: dict[str, tuple[list[np.ndarray], list[np.ndarray]]] = {}  #: process trace -> points, colours
        self._process_nodes: dict[str, list[Any]] = {}
        self._caption: Any = None
        self._flange: Any = None                  #: the flange's mount, made when a tool is mounted on it
        self.scene.set_up_direction("+z")
        # Shadows off unless asked for: in software WebGL (a machine without a GPU, the headless browser of the tests)
        # the default light's three shadow cascades make each frame several times dearer (bench_view --shadows).
        self.scene.configure_default_lights(enabled=True, cast_shadow=shadows)
        if not environment_map:
            # Without an environment map of its own the page lights every surface from viser's default one, sampled
            # for each pixel: in software WebGL that was three quarters of a frame (bench_view: gpu_cpu_ms_per_frame
            # against `_with_environment_map`). A light from the sky and the ground fills in what it lit.
            self.scene.configure_environment_map(None)
            self.scene.add_light_hemisphere("/lights/fill", sky_color=(255, 255, 255), ground_color=FILL_GROUND_RGB,
                                            intensity=FILL_INTENSITY)

    # -- the cell (MuJoCo geoms) -------------------------------------------------------------

    def add_cell(self, shapes: tuple[Shape, ...], poses: Poses) -> None:
        """Every geom of the compiled cell at its current pose."""
        for shape in shapes:
            node = self._add_shape(f"/cell/{shape.name}", shape)
            node.position = poses.position_m[shape.index]
            node.wxyz = poses.wxyz[shape.index]
            self.shapes[shape.name] = node
            if shape.moves:
                self.moving[shape.index] = node

    def _add_shape(self, name: str, shape: Shape) -> Any:
        scene, rgb, size = self.scene, _rgb(shape.rgba), shape.size_m
        opacity = None if shape.rgba[3] >= 1.0 else shape.rgba[3]
        if shape.kind == "box":
            return scene.add_box(name, rgb, tuple(2 * s for s in size), opacity=opacity)
        if shape.kind == "sphere":
            return scene.add_icosphere(name, size[0], rgb, opacity=opacity)
        if shape.kind == "ellipsoid":
            return scene.add_icosphere(name, 1.0, rgb, scale=size, opacity=opacity)
        if shape.kind == "cylinder":
            return scene.add_cylinder(name, size[0], 2 * size[1], rgb, opacity=opacity)
        if shape.kind == "capsule":  # a cylinder with a sphere at each end, moved as one group
            group = scene.add_frame(name, show_axes=False)
            scene.add_cylinder(f"{name}/body", size[0], 2 * size[1], rgb, opacity=opacity)
            for end, z in (("top", size[1]), ("bottom", -size[1])):
                scene.add_icosphere(f"{name}/{end}", size[0], rgb, position=(0.0, 0.0, z), opacity=opacity)
            return group
        if shape.kind == "mesh":
            return scene.add_mesh_simple(name, shape.vertices_m, shape.faces, color=rgb, opacity=opacity)
        # a plane: MuJoCo's size is its half extents (0: infinite, drawn as the floor the cell stands on)
        width = 2 * size[0] if size[0] > 0 else 10.0
        height = 2 * size[1] if size[1] > 0 else 10.0
        return scene.add_grid(name, width, height, cell_size=0.25, section_size=1.0, plane_color=rgb, plane_opacity=0.5)

    def show(self, frames: Frames | None, flange: np.ndarray | None, caption: str) -> None:
        """One update of the run: the moving geoms (MuJoCo's rotation matrices), the flange (4x4), the caption."""
        if frames is not None:
            self.move_cell(Poses(frames.time_s, frames.position_m, wxyz_of_many(frames.rotation)))
        if flange is not None and self._flange is not None:
            self._flange.position = flange[:3, 3]
            self._flange.wxyz = wxyz_of(flange[:3, :3])
        self.set_caption(caption)

    def together(self) -> Any:
        """A block whose messages a browser applies together (viser's atomic), sent as one: each message outside one
        wakes the server's sending loop, a thread switch of the view's process (bench_view: its CPU per update)."""
        return self.server.atomic()

    def move_cell(self, poses: Poses) -> None:
        """The moving geoms where the plant has them now, sent together so a browser never shows half a robot."""
        with self.server.atomic():
            for index, node in self.moving.items():
                node.position = poses.position_m[index]
                node.wxyz = poses.wxyz[index]

    # -- the world model: objects, frames, their names ----------------------------------------

    def add_object(self, name: str, world_t: np.ndarray, model: Any, parent_node: str = "/world") -> None:
        """A world object: its frame with its name, and its geometry (box, cylinder, sphere) where the model says."""
        if parent_node == FLANGE_NODE and self._flange is None:
            self._flange = self.add_mount(FLANGE_NODE)
        node_name = f"{parent_node}/{name}"
        node = self.scene.add_frame(node_name, axes_length=OBJECT_AXES_M, axes_radius=0.004,
                                    position=world_t[:3, 3], wxyz=wxyz_of(world_t[:3, :3]))
        self.scene.add_label(f"{node_name}/name", name, font_screen_scale=0.9)
        self.objects[name] = node
        if model is not None and model.geometry in ("box", "cylinder", "sphere") and model.size_m:
            offset = model.offset.matrix() if model.offset is not None else np.eye(4)
            where = {"position": offset[:3, 3], "wxyz": wxyz_of(offset[:3, :3])}
            rgb, size = _colour(model.colour), model.size_m
            if model.geometry == "box":
                self.scene.add_box(f"{node_name}/geometry", rgb, tuple(size), **where)
            elif model.geometry == "cylinder":
                self.scene.add_cylinder(f"{node_name}/geometry", size[0], size[1], rgb, **where)
            else:
                self.scene.add_icosphere(f"{node_name}/geometry", size[0], rgb, **where)

    def add_mount(self, name: str) -> Any:
        """An invisible node that carries what is mounted on it (the flange carries tools); move it with set_mount."""
        return self.scene.add_frame(name, show_axes=False)

    # -- positions, planned paths, the TCP trace -------------------------------------------------

    def set_position(self, name: str, world_t: np.ndarray) -> None:
        """A declared position as a small frame with its name (moved if it is declared again)."""
        node = self.positions.get(name)
        if node is None:
            node = self.scene.add_frame(f"/positions/{name}", axes_length=POSITION_AXES_M, axes_radius=0.003)
            self.scene.add_label(f"/positions/{name}/name", name, font_screen_scale=0.8)
            self.positions[name] = node
        node.position = world_t[:3, 3]
        node.wxyz = wxyz_of(world_t[:3, :3])

    def show_position(self, label: str, world_t: np.ndarray) -> None:
        """A declared position; an off-line program's positions are the world's frames under short names: drawn once."""
        if label not in self.positions:
            same = [node for key, node in (*self.objects.items(), *self.positions.items())
                    if key == label or key.endswith(f".{label}")]
            if any(np.allclose(node.position, world_t[:3, 3], atol=1e-6) for node in same):
                return
        self.set_position(label, world_t)

    def remove_positions(self, names: list[str]) -> None:
        """Take positions off the screen (a position deleted or renamed in the pendant)."""
        for name in names:
            node = self.positions.pop(name, None)
            if node is not None:
                node.remove()

    def add_path(self, move_id: int, tcp_m: np.ndarray) -> None:
        """The TCP path a move is planned to take, drawn before it starts."""
        points = np.asarray(tcp_m, dtype=np.float32)
        if len(points) < 2:
            return
        segments = np.stack([points[:-1], points[1:]], axis=1)
        # Every path in colours per vertex, as the trace: the page draws both with one shader program (one fewer to
        # compile when the first path arrives). The oldest path's node shows the new path once PATHS_KEPT are on
        # screen: updating a node costs this process and the page less than making one and removing another.
        colours = _per_vertex(PATH_RGB, segments.shape)
        node = self.paths.pop(move_id, None)  # a move drawn again: its node shows the new plan
        if node is None and len(self.paths) >= PATHS_KEPT:
            node = self.paths.pop(next(iter(self.paths)))
        if node is None:
            node = self.scene.add_line_segments(f"/paths/{self._path_nodes}", segments, colours, thickness=3.0,
                                                thickness_units="screen")
            self._path_nodes += 1
        else:
            with self.server.atomic():
                node.points, node.colors, node.thickness = segments, colours, 3.0
        self.paths[move_id] = node

    def extend_trace(self, points_m: list[np.ndarray]) -> None:
        """Add TCP positions to the trace; only its newest chunk is sent again."""
        if not points_m:
            return
        self.trace_m.extend(points_m)
        self._extend_line("/trace", self._trace_nodes, self.trace_m, None, TRACE_RGB, 2.0)

    def extend_process(self, name: str, points_m: list[np.ndarray], colours: np.ndarray) -> None:
        """Add points to a process trace (the tracked seam, the ground edge), each with its colour (RGB 0..255)."""
        if not points_m:
            return
        trace = self.process.setdefault(name, ([], []))
        trace[0].extend(points_m)
        trace[1].extend(colours)
        self._extend_line(f"/process/{name}", self._process_nodes.setdefault(name, []), trace[0], trace[1],
                          PATH_RGB, 5.0)

    def _extend_line(self, prefix: str, nodes: list[Any], points: list[np.ndarray], colours: list[np.ndarray] | None,
                     rgb: tuple[int, int, int], thickness: float) -> None:
        """Draw a growing polyline in chunks of TRACE_CHUNK points: only the newest chunk is sent again."""
        first = (len(nodes) - 1) * TRACE_CHUNK if nodes else 0
        while True:
            chunk = np.asarray(points[first: first + TRACE_CHUNK + 1], dtype=np.float32)
            index = first // TRACE_CHUNK
            if len(chunk) >= 2:
                segments = np.stack([chunk[:-1], chunk[1:]], axis=1)
                if colours is None:
                    segment_colours = _per_vertex(rgb, segments.shape)
                else:  # a segment takes the colours of its two ends
                    ends = np.asarray(colours[first: first + TRACE_CHUNK + 1], dtype=np.uint8)
                    segment_colours = np.stack([ends[:-1], ends[1:]], axis=1)
                if index < len(nodes):
                    with self.server.atomic():
                        nodes[index].points = segments
                        nodes[index].colors = segment_colours
                else:
                    nodes.append(self.scene.add_line_segments(f"{prefix}/{index}", segments, segment_colours,
                                                              thickness=thickness, thickness_units="screen"))
            if first + TRACE_CHUNK + 1 >= len(points):
                return
            first += TRACE_CHUNK

    def add_weld(self, number: int, position_m: tuple[float, float, float], good: bool, reason: str) -> None:
        """A spot weld where the gun closed: green when good, red with the reason when not."""
        name = f"/process/welds/{number}"
        self.welds[number] = self.scene.add_icosphere(name, WELD_RADIUS_M, GOOD_RGB if good else BAD_RGB,
                                                      position=position_m)
        text = f"weld {number}" if good else f"weld {number}: {reason}"
        self.scene.add_label(f"{name}/name", text, font_screen_scale=0.7)

    def highlight(self, position: str | None = None, move_id: int | None = None) -> None:
        """Show one position larger (None: none) and one move's planned path in blue and thicker (None: none)."""
        for name, node in self.positions.items():
            node.scale = HIGHLIGHT_SCALE if name == position else 1.0
        for key, node in self.paths.items():
            chosen = key == move_id
            node.thickness = 6.0 if chosen else 3.0
            node.colors = _per_vertex(HIGHLIGHT_RGB if chosen else PATH_RGB, node.points.shape)

    # -- words and the camera -------------------------------------------------------------

    @property
    def caption(self) -> str:
        """The caption's text now (empty before the first)."""
        return self._caption.content if self._caption is not None else ""

    def set_caption(self, text: str) -> None:
        """The line under the title: the simulated time and the statement the program is at."""
        if self._caption is None:
            self._caption = self.server.gui.add_markdown(text)
        elif self._caption.content != text:
            self._caption.content = text

    def frame_camera(self, framing: Framing) -> None:
        """Where a newly opened page looks from."""
        self.server.initial_camera.look_at = framing.lookat_m
        self.server.initial_camera.position = framing.camera_position_m()
        self.server.initial_camera.up = (0.0, 0.0, 1.0)


def _per_vertex(rgb: tuple[int, int, int], shape: tuple[int, ...]) -> np.ndarray:
    """One colour for every vertex of line segments of this shape (n, 2, 3)."""
    return np.broadcast_to(np.array(rgb, dtype=np.uint8), shape).copy()


def _colour(colour: str | tuple[float, ...] | None) -> tuple[int, int, int]:
    """A world model's colour (a name or [r, g, b(, a)] in 0..1) as RGB 0..255; grey when none is given."""
    from matplotlib.colors import to_rgba

    if colour is None:
        return (160, 160, 160)
    try:
        return _rgb(to_rgba(colour))
    except ValueError:  # the world loader checked it; a name matplotlib does not know stays grey
        return (160, 160, 160)
