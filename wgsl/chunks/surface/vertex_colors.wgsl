#if VERTEX_COLORS
// Vertex colors: the mesh's colors multiply the material's ambient and diffuse (OpenGL's
// GL_COLOR_MATERIAL with GL_AMBIENT_AND_DIFFUSE; glTF's COLOR_0 times the base color),
// and its alpha the surface's.
// The vertex color at the point being shaded, set before shade() runs.
var<private> surface_color: vec4<f32> = vec4<f32>(1.0);

#at lighting.surface_tint
    tint = surface_color.rgb;
#end
#at output.surface_alpha
    alpha *= surface_color.a;
#end
#at phong.varyings
    @location(3) color: vec4<f32>,
#end
#at phong.vertex
    out.color = vertex.color;
#end
#at phong.fragment_surface
    surface_color = in.color;
#end
#at gouraud.vertex_surface
    surface_color = vertex.color;
#end
#at points.varyings
    @location(0) @interpolate(flat) color: vec4<f32>,
#end
#at lines.varyings
    @location(0) color: vec4<f32>,
#end
#at points.vertex
    out.color = vertex.color;
#end
#at lines.vertex
    // interpolated from one end of the segment to the other
    out.color = select(vertex.start_color, vertex.end_color, corner.x > 0.5);
#end
#at points.fragment_surface lines.fragment_surface
    surface_color = in.color;
#end
#at flat.vertex_surface
    // One color per face, like its normal: the mean of its corners' colors.
    surface_color = (mesh_colors[mesh_indices[first]] + mesh_colors[mesh_indices[first + 1u]]
        + mesh_colors[mesh_indices[first + 2u]]) / 3.0;
#end
#endif
