"""Off-screen OpenGL renderer of a world's colour and thermal images (moderngl).

Runs on any OpenGL 3.3 driver: on a machine without a GPU, Mesa's llvmpipe through EGL (headless,
no X server); with a GPU, its EGL driver. The scene is two vertex buffers (static world and
dynamic objects, see :mod:`sim.render.scene`) drawn with a depth test; one program shades colour,
another writes surface temperature into a float framebuffer. Framebuffers are kept per image size.
"""

from __future__ import annotations

import zlib
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import moderngl
import numpy as np
from numpy.typing import NDArray

from hdrc3_base.errors import Hdrc3Error
from sim.render.imaging import ColorImaging, ThermalImaging, thermal_counts
from sim.render.materials import ThermalEnvironment
from sim.render.projection import clip_matrix, gl_bytes
from sim.render.scene import object_mesh, static_mesh
from sim.render.tiles import TiledMesh, ranges, tile_mesh
from sim.sensors.camera_model import CameraPose, Intrinsics
from sim.world import DynamicObject, World

_VERTEX = """
#version 330
uniform mat4 clip;
in vec3 in_pos;
in vec3 in_normal;
in vec3 in_albedo;
in float in_temp;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_albedo;
out float v_temp;
void main() {
    v_world = in_pos;
    v_normal = in_normal;
    v_albedo = in_albedo;
    v_temp = in_temp;
    gl_Position = clip * vec4(in_pos, 1.0);
}
"""
_HASH = """
float hash(vec2 p) {
    p = fract(p * vec2(443.897, 441.423));
    p += dot(p, p.yx + 19.19);
    return fract((p.x + p.y) * p.x);
}
// smooth value noise in [0, 1): hashes of the cell corners, blended with a smoothstep
float vnoise(vec2 p) {
    vec2 i = floor(p);
    vec2 f = fract(p);
    vec2 s = f * f * (3.0 - 2.0 * f);
    float a = mix(hash(i), hash(i + vec2(1.0, 0.0)), s.x);
    float b = mix(hash(i + vec2(0.0, 1.0)), hash(i + vec2(1.0, 1.0)), s.x);
    return mix(a, b, s.y);
}
"""
_COLOR = (
    """
#version 330
uniform vec3 sun_dir;
uniform float sun;
uniform float ambient;
uniform float exposure;
uniform float noise;
uniform float seed;
uniform float texture_amp;
in vec3 v_world;
in vec3 v_normal;
in vec3 v_albedo;
in float v_temp;
out vec4 colour;
"""
    + _HASH
    + """
void main() {
    vec3 n = normalize(v_normal);
    float grain = 1.0 + texture_amp * (0.65 * vnoise(v_world.xy * 3.0)
                                       + 0.35 * vnoise(v_world.xy * 11.0) - 0.5);
    float light = ambient + sun * max(dot(n, sun_dir), 0.0);
    vec3 c = v_albedo * grain * light * exposure;
    // zero-mean noise per pixel and channel (uniform of the same variance as the sigma)
    vec2 px = gl_FragCoord.xy + vec2(seed, 1.7 * seed);
    vec3 u = vec3(hash(px), hash(px + 37.0), hash(px + 91.0)) - 0.5;
    colour = vec4(clamp(c + noise * 3.4641 * u, 0.0, 1.0), 1.0);
}
"""
)
_THERMAL = (
    """
#version 330
uniform float texture_amp;
in vec3 v_world;
in vec3 v_normal;
in vec3 v_albedo;
in float v_temp;
out float temperature;
"""
    + _HASH
    + """
void main() {
    temperature = v_temp + texture_amp * (vnoise(v_world.xy * 1.5) - 0.5);
}
"""
)
GROUND_GRAIN = 0.35
"""Relative albedo variation of the static scene's texture (value noise, 33 cm and 9 cm)."""
GROUND_THERMAL_GRAIN_K = 0.8
"""Temperature variation of the static scene (value noise, 67 cm)."""


class RenderError(Hdrc3Error):
    """No OpenGL context could be created (no EGL driver installed)."""


def _context() -> moderngl.Context:
    try:
        options: dict[str, Any] = {"backend": "egl"}  # typed as a dict in moderngl's stubs
        return moderngl.create_standalone_context(**options)
    except Exception as exc:  # moderngl raises plain Exception when EGL is missing
        raise RenderError(
            f"no OpenGL context through EGL ({exc}); on Debian install libegl1 libegl-mesa0 "
            "libgl1-mesa-dri libgbm1"
        ) from exc


@dataclass(frozen=True, slots=True)
class _Drawable:
    """One vertex buffer, tiled for culling, bound to both programs."""

    mesh: TiledMesh
    vbo: moderngl.Buffer
    colour: moderngl.VertexArray
    thermal: moderngl.VertexArray

    def release(self) -> None:
        """Free the GL objects (the context does not collect them)."""
        self.colour.release()
        self.thermal.release()
        self.vbo.release()


def _uniform(program: moderngl.Program, name: str) -> moderngl.Uniform:
    member = program[name]
    assert isinstance(member, moderngl.Uniform), name
    return member


class Renderer:
    """Renders colour and thermal images of one world from any camera pose."""

    def __init__(
        self,
        world: World,
        color: ColorImaging | None = None,
        thermal: ThermalImaging | None = None,
        environment: ThermalEnvironment | None = None,
        seed: int = 0,
    ) -> None:
        """Create the GL context and upload the world's meshes (objects from the world file)."""
        self.world = world
        self.color = color or ColorImaging()
        self.thermal = thermal or ThermalImaging()
        self.environment = environment or ThermalEnvironment()
        self.seed = seed
        self.ctx = _context()
        self.ctx.enable(moderngl.DEPTH_TEST)
        self._color_prog = self.ctx.program(vertex_shader=_VERTEX, fragment_shader=_COLOR)
        self._thermal_prog = self.ctx.program(vertex_shader=_VERTEX, fragment_shader=_THERMAL)
        self._static = self._buffers(static_mesh(world, self.environment))
        self._parked: tuple[DynamicObject, ...] = ()
        self._objects: _Drawable | None = None
        self._driving: _Drawable | None = None
        self._framebuffers: dict[tuple[int, int, bool], moderngl.Framebuffer] = {}
        prog = self._color_prog
        _uniform(prog, "sun_dir").value = self.color.sun_direction()
        _uniform(prog, "sun").value = self.color.sun
        _uniform(prog, "ambient").value = self.color.ambient
        _uniform(prog, "exposure").value = self.color.exposure
        _uniform(prog, "noise").value = self.color.noise
        self.set_objects(world.objects)  # last: leaving its `with self.ctx` unbinds the context

    @property
    def renderer_name(self) -> str:
        """The OpenGL renderer string (``llvmpipe ...`` without a GPU)."""
        with self.ctx:
            return str(self.ctx.info["GL_RENDERER"])

    def _buffers(self, vertices: NDArray[np.float32]) -> _Drawable | None:
        if vertices.shape[0] == 0:
            return None
        tiled = tile_mesh(vertices)
        vbo = self.ctx.buffer(np.ascontiguousarray(tiled.vertices).tobytes())
        # Each program binds only the attributes it reads (the rest is skipped by byte count).
        colour = self.ctx.vertex_array(
            self._color_prog, [(vbo, "3f 3f 3f 4x", "in_pos", "in_normal", "in_albedo")]
        )
        thermal = self.ctx.vertex_array(
            self._thermal_prog, [(vbo, "3f 24x 1f", "in_pos", "in_temp")]
        )
        return _Drawable(tiled, vbo, colour, thermal)

    def set_objects(self, objects: Iterable[DynamicObject]) -> None:
        """Replace the dynamic objects (after a spawn or a move).

        Driving cars move with every ``/world_sim/objects`` message (10 Hz of sim time): they
        have their own small buffer, rebuilt each time, while the mesh of the other objects
        (people's bodies are most of its triangles) is rebuilt only when one of them changed.
        """
        objects = list(objects)
        parked = tuple(obj for obj in objects if obj.drive is None)
        driving = [obj for obj in objects if obj.drive is not None]
        with self.ctx:
            if parked != self._parked or self._objects is None:
                self._parked = parked
                self._objects = self._replace(self._objects, parked)
            self._driving = self._replace(self._driving, driving)

    def _replace(self, old: _Drawable | None, objects: Iterable[DynamicObject]) -> _Drawable | None:
        if old is not None:
            old.release()
        return self._buffers(object_mesh(self.world, objects, self.environment))

    def _framebuffer(self, intrinsics: Intrinsics, thermal: bool) -> moderngl.Framebuffer:
        key = (intrinsics.width, intrinsics.height, thermal)
        fbo = self._framebuffers.get(key)
        if fbo is None:
            size = (intrinsics.width, intrinsics.height)
            target = (
                self.ctx.renderbuffer(size, components=1, dtype="f4")
                if thermal
                else self.ctx.renderbuffer(size, components=4)
            )
            fbo = self.ctx.framebuffer([target], self.ctx.depth_renderbuffer(size))
            self._framebuffers[key] = fbo
        return fbo

    def _draw(
        self, pose: CameraPose, intrinsics: Intrinsics, thermal: bool
    ) -> moderngl.Framebuffer:
        fbo = self._framebuffer(intrinsics, thermal)
        fbo.use()
        if thermal:
            fbo.clear(self.environment.sky, 0.0, 0.0, 0.0, depth=1.0)
        else:
            fbo.clear(*self.color.sky, 1.0, depth=1.0)
        prog = self._thermal_prog if thermal else self._color_prog
        clip = clip_matrix(pose, intrinsics)
        _uniform(prog, "clip").write(gl_bytes(clip))
        drawables = ((self._static, True), (self._objects, False), (self._driving, False))
        for drawable, grain in drawables:
            if drawable is None:
                continue
            amp = (GROUND_THERMAL_GRAIN_K if thermal else GROUND_GRAIN) if grain else 0.0
            if "texture_amp" in prog:  # the thermal shader may optimise it away
                _uniform(prog, "texture_amp").value = amp
            vao = drawable.thermal if thermal else drawable.colour
            for first, count in ranges(drawable.mesh, clip):
                vao.render(moderngl.TRIANGLES, vertices=count, first=first)
        return fbo

    def frame_rng(self, stamp_ns: int, camera: int) -> np.random.Generator:
        """The noise stream of one frame: the same seed, stamp and camera give the same noise."""
        return np.random.default_rng([self.seed, camera, stamp_ns % (1 << 62)])

    def render_color(
        self, pose: CameraPose, intrinsics: Intrinsics, stamp_ns: int = 0
    ) -> NDArray[np.uint8]:
        """RGB image (height, width, 3), row 0 at the top."""
        seed = float(self.frame_rng(stamp_ns, 0).integers(0, 4096))
        with self.ctx:  # another renderer of this process may have made its context current
            _uniform(self._color_prog, "seed").value = seed
            fbo = self._draw(pose, intrinsics, thermal=False)
            data = fbo.read(components=3, alignment=1)
        return np.frombuffer(data, dtype=np.uint8).reshape(intrinsics.height, intrinsics.width, 3)

    def render_temperature(self, pose: CameraPose, intrinsics: Intrinsics) -> NDArray[np.float32]:
        """Noise-free surface temperature (height, width), K, row 0 at the top."""
        with self.ctx:
            fbo = self._draw(pose, intrinsics, thermal=True)
            data = fbo.read(components=1, dtype="f4", alignment=1)
        return np.frombuffer(data, dtype=np.float32).reshape(intrinsics.height, intrinsics.width)

    def render_thermal(
        self, pose: CameraPose, intrinsics: Intrinsics, stamp_ns: int = 0
    ) -> NDArray[np.uint16]:
        """Thermal image (height, width) in centi-kelvin: optics blur and detector noise."""
        kelvin = self.render_temperature(pose, intrinsics)
        return thermal_counts(kelvin, self.thermal, self.frame_rng(stamp_ns, 1))

    def release(self) -> None:
        """Free the GL context."""
        self.ctx.release()


def digest(image: NDArray[np.generic]) -> int:
    """A cheap content checksum of an image (tests: frozen frames repeat the same bytes)."""
    return zlib.crc32(np.ascontiguousarray(image).tobytes())
