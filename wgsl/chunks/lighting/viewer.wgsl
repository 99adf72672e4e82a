// The viewer: where V points from the shaded point.

// Unit vector from the shaded point to the viewer.
fn view_direction(eye_position: vec3<f32>, normal: vec3<f32>) -> vec3<f32> {
#if LOCAL_VIEWER
    // The seeds' shaders: V = normalize(−P). An eye exactly on the surface looks along N.
    return safe_normalize(-eye_position, normal);
#else
    // OpenGL's default infinite viewer (GL_LIGHT_MODEL_LOCAL_VIEWER false).
    return vec3<f32>(0.0, 0.0, 1.0);
#endif
}
