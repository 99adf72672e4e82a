#if EDGES
// A triangle mesh's edges (`--edges`, docs/primitives.md#edges): lines in the edge colour,
// written as it is (a colour on the image, like the background; its alpha blends).
#at output.surface
    rgb = object_uniforms.edge_color.rgb;
    alpha = object_uniforms.edge_color.a;
#end
#endif
