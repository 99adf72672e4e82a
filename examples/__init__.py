# The example scenes and sample meshes; installed as the package `wgpu_shading.examples`.
