"""The cold-start peer: the smallest moderngl program that does what
`wgpu-shading render builtin:torus -o OUT.png` does: the seed's torus (48×48 segments),
the seed's GLSL Phong shaders, 512×512 with a depth buffer, read back, written as PNG.

    python benchmarks/scripts/moderngl_torus.py OUT.png [SIZE]

SIZE: the image side (default 512, the CLI's default).
"""

import math
import sys

import imageio.v3 as iio
import moderngl
import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0] + "/..")
from seed_glsl import SEED_FRAGMENT_SHADER, SEED_VERTEX_SHADER  # noqa: E402

size = int(sys.argv[2]) if len(sys.argv) > 2 else 512
segments, major, minor = 48, 0.5, 0.2
a, t = np.meshgrid(np.linspace(0, 2 * np.pi, segments + 1), np.linspace(0, 2 * np.pi, segments + 1), indexing="ij")
normal = np.stack([np.cos(t) * np.cos(a), np.sin(t), -np.cos(t) * np.sin(a)], -1).reshape(-1, 3)
centre = np.stack([major * np.cos(a), np.zeros_like(a), -major * np.sin(a)], -1).reshape(-1, 3)
positions = (centre + minor * normal).astype("f4")
i, j = (x.reshape(-1) for x in np.meshgrid(np.arange(segments), np.arange(segments), indexing="ij"))
c = segments + 1
indices = np.concatenate([np.stack([i * c + j, (i + 1) * c + j, (i + 1) * c + j + 1], 1),
                          np.stack([i * c + j, (i + 1) * c + j + 1, i * c + j + 1], 1)]).astype("u4")

ctx = moderngl.create_standalone_context(backend="egl", require=430)
program = ctx.program(vertex_shader=SEED_VERTEX_SHADER, fragment_shader=SEED_FRAGMENT_SHADER)
# The CLI's framing: camera 1.05 bounding radii / sin(fov/2) away, a little above; light up right.
radius = float(np.linalg.norm(positions.max(0) - positions.min(0))) / 2
distance = radius / math.sin(math.radians(22.5)) * 1.05
eye = np.array([0.0, 0.35, 1.0]) / np.linalg.norm([0.0, 0.35, 1.0]) * distance
light = np.array([5.0, 2.0, 2.0]) * radius * 1.5
forward = -eye / np.linalg.norm(eye)
right = np.cross(forward, [0, 1, 0]); right /= np.linalg.norm(right)
up = np.cross(right, forward)
view = np.eye(4); view[0, :3], view[1, :3], view[2, :3] = right, up, -forward; view[:3, 3] = -view[:3, :3] @ eye
near, far, focal = max(distance - 1.5 * radius, distance * 1e-3), distance + 1.5 * radius, 1 / math.tan(math.radians(22.5))
projection = np.array([[focal, 0, 0, 0], [0, focal, 0, 0], [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])
program["mv_matrix"].write(view.T.astype("f4").tobytes())
program["proj_matrix"].write(projection.T.astype("f4").tobytes())
program["norm_matrix"].write(np.linalg.inv(view).astype("f4").tobytes())
for name, value in {"globalAmbient": (0.2, 0.2, 0.2, 1), "light.diffuse": (1, 1, 1, 1), "light.specular": (1, 1, 1, 1),
                    "light.position": tuple((view @ [*light, 1])[:3]), "material.ambient": (0.2473, 0.1995, 0.0745, 1),
                    "material.diffuse": (0.7516, 0.6065, 0.2265, 1), "material.specular": (0.6283, 0.5558, 0.3661, 1),
                    "material.shininess": 51.2}.items():
    if name in program:
        program[name].value = value
vao = ctx.vertex_array(program, [(ctx.buffer(positions.tobytes()), "3f", "vertPos"), (ctx.buffer(normal.astype("f4").tobytes()), "3f", "vertNormal")],
                       index_buffer=ctx.buffer(indices.tobytes()), index_element_size=4)
fbo = ctx.framebuffer(color_attachments=[ctx.renderbuffer((size, size), components=4)], depth_attachment=ctx.depth_renderbuffer((size, size)))
fbo.use()
ctx.enable(moderngl.DEPTH_TEST)
fbo.clear(0, 0, 0, 1, depth=1.0)
vao.render(moderngl.TRIANGLES)
image = np.frombuffer(fbo.read(components=4), np.uint8).reshape(size, size, 4)[::-1]
iio.imwrite(sys.argv[1], image)
