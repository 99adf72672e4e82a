#if TWO_SIDED
// Two-sided lighting (GL_LIGHT_MODEL_TWO_SIDE): back faces are lit with the flipped normal.
#at phong.fragment_inputs vertex_lit.fragment_inputs
    @builtin(front_facing) front_facing: bool,
#end
#at phong.fragment_normal
    if (!front_facing) {
        normal = -normal;
        face_sign = -1.0;
    }
#end

// Flat and Gouraud shading compute a second color per vertex for back faces, lit with -N,
// and each fragment picks one.
#at gouraud.varyings
    @location(2) back_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(3) back_specular: vec3<f32>,
#endif
#end
#at flat.varyings
    @location(2) @interpolate(flat) back_ambient_diffuse: vec3<f32>,
#if SPECULAR
    @location(3) @interpolate(flat) back_specular: vec3<f32>,
#endif
#end
#at vertex_lit.store
    let back = vertex_color(eye_position, -normal);
    (*out).back_ambient_diffuse = back.ambient_diffuse;
#if SPECULAR
    (*out).back_specular = back.specular;
#endif
#end
#at vertex_lit.fragment_lit
    if (!front_facing) {
        lit.ambient_diffuse = in.back_ambient_diffuse;
#if SPECULAR
        lit.specular = in.back_specular;
#endif
    }
#end
#endif
