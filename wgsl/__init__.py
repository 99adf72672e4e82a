# The WGSL shader sources. This folder is installed as the package `wgpu_shading.wgsl`
# (see pyproject.toml) so the files ship in the wheel; this file only makes it a package.
