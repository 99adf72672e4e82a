#if SHADOWS
// Shadows (docs/shadows.md): the visibility V of a casting light at this fragment, read from
// its shadow maps. The maps (a layer of `shadow_maps` per view) hold the reversed depth of
// the casters nearest the light; render/passes/shadow_views.py fits the views and the shadow
// pass draws them. The light chunks (visibility.wgsl) ask for V by the light's slot.
//
// A texel is compared with the receiver's own triangle, not with its point alone: the depth
// the triangle's plane has on that texel's ray (the tangent plane of Dou et al. 2014,
// "Adaptive depth bias for shadow maps", https://doi.org/10.1145/2556700.2556706). A plane's
// depth changes across one texel by tan(angle to the light) texels, without bound at a
// grazing light; compared this way the receiver meets itself exactly, and the bias (texels of
// the map, not world units) only covers rounding and concave curvature.

// Each casting light's view of the fragment's point: transformed per vertex (light-space
// coordinates are affine in the position, so interpolating them is exact) rather than per
// fragment, where every uniform component read costs llvmpipe a gather. At most
// MAX_SHADOW_LIGHTS (Phong) or MAX_VERTEX_LIT_SHADOW_LIGHTS (flat, Gouraud: their shares
// take locations 6..21) casting lights (render/features.py).
#at phong.varyings
#for LIGHT < SHADOW_LIGHTS
    @location({{5 + LIGHT}}) shadow_position_{{LIGHT}}: vec3<f32>,
#endfor
#end
#at gouraud.varyings flat.varyings
#for LIGHT < SHADOW_LIGHTS
    @location({{22 + LIGHT}}) shadow_position_{{LIGHT}}: vec3<f32>,
#endfor
#end

// The vertex's (a flat face's: the corner's) point in each casting light's view.
fn light_position(slot: u32, eye_position: vec4<f32>) -> vec3<f32> {
    return (shadow_uniforms.lights[slot].light_from_eye * eye_position).xyz;
}
#at phong.vertex gouraud.vertex
#for LIGHT < SHADOW_LIGHTS
    out.shadow_position_{{LIGHT}} = light_position({{LIGHT}}u, eye_position);
#endfor
#end
#at flat.vertex
    let corner_position = object_uniforms.eye_from_model * vec4<f32>(corner, 1.0);
#for LIGHT < SHADOW_LIGHTS
    out.shadow_position_{{LIGHT}} = light_position({{LIGHT}}u, corner_position);
#endfor
#end

// The receiver at this fragment in each casting light's view: its point, and its
// triangle's outward unit normal (the side its winding calls front).
var<private> shadow_points: array<vec3<f32>, SHADOW_LIGHT_COUNT>;
var<private> shadow_normals: array<vec3<f32>, SHADOW_LIGHT_COUNT>;

// Below this sine of the angle between ∂q/∂x and ∂q/∂y the triangle is a sliver edge-on to
// the camera, a fraction of a pixel wide: the rasterizer's front_facing comes from its
// corners snapped to the subpixel grid, the derivatives from the unsnapped ones, and the two
// may disagree on which side is seen (random scene 74: a torus facet at N·V = 0.005 on its
// silhouette, lit by both lights, read as the far side of a closed surface).
const MIN_DERIVATIVE_SINE: f32 = 0.02;

// Whether the fragment's outward side is known (not such a sliver): the closed-surface
// rule needs it; the comparison with the receiver's plane does not (a plane is the same
// whichever way its normal points).
var<private> outward_known: bool = true;

// The outward normal of the fragment's triangle in a light's view, from the screen
// derivatives of its point there (they lie in the triangle, at every shading frequency;
// framebuffer y points down, so −(∂q/∂x × ∂q/∂y) points to the side the camera sees).
// Called first thing by the fragment stage: derivatives need uniform control flow.
fn outward_normal(q: vec3<f32>, front_facing: bool) -> vec3<f32> {
    let across = safe_normalize(dpdx(q), vec3<f32>(1.0, 0.0, 0.0));
    let down = safe_normalize(dpdy(q), vec3<f32>(0.0, 1.0, 0.0));
    let perpendicular = cross(across, down);
    // (The angle between the derivatives is the same in every light's view: rigid turns.)
    outward_known = dot(perpendicular, perpendicular) >= MIN_DERIVATIVE_SINE * MIN_DERIVATIVE_SINE;
    let seen_side = -safe_normalize(perpendicular, vec3<f32>(0.0, 0.0, 1.0));
    return select(-seen_side, seen_side, front_facing) * object_uniforms.outward_sign;
}

// The fragment stage knows its receiver before anything else (visibility.wgsl declares
// front_facing where two-sided lighting does not).
#at phong.fragment_begin vertex_lit.fragment_begin
#for LIGHT < SHADOW_LIGHTS
    shadow_points[{{LIGHT}}] = in.shadow_position_{{LIGHT}};
    shadow_normals[{{LIGHT}}] = outward_normal(in.shadow_position_{{LIGHT}}, front_facing);
#endfor
#end

// The steepest plane the comparison extends, in distance per unit across the light: an
// edge-on triangle is extended at this slope (finite numbers, the same answer).
const MAX_SHADOW_SLOPE: f32 = 1e6;

// The receiver in a light's view — its point q and outward normal n in the view's space,
// where the fragment falls in the map (texel coordinates) and the map's layer (−1: none) —
// in a single map's view, or for a cube map in the view of the face its direction
// from the light falls in (the largest axis: +X, −X, +Y, −Y, +Z, −Z). Each face reaches a guard band past its edges, so a point near an edge
// finds every texel of its filter in its own face: no seams.
struct ShadowReceiver {
    q: vec3<f32>,
    n: vec3<f32>,
    sample: vec2<f32>,
    layer: i32,
}

fn shadow_receiver(light: ShadowLight, slot: u32, orthographic: bool) -> ShadowReceiver {
    var receiver: ShadowReceiver;
    receiver.q = shadow_points[slot];
    receiver.n = shadow_normals[slot];
    receiver.layer = light.layers.x;
    if (light.more_layers.z != 0) {
        // The face: the largest axis of the direction from the light, and its sign.
        let size = abs(receiver.q);
        let x_major = size.x >= size.y && size.x >= size.z;
        let y_major = !x_major && size.y >= size.z;
        let axis = select(select(receiver.q.z, receiver.q.y, y_major), receiver.q.x, x_major);
        let positive = axis >= 0.0;
        receiver.q = cube_face_turn(receiver.q, x_major, y_major, positive);
        receiver.n = cube_face_turn(receiver.n, x_major, y_major, positive);
        let x_layer = select(light.layers.y, light.layers.x, positive);
        let y_layer = select(light.layers.w, light.layers.z, positive);
        let z_layer = select(light.more_layers.y, light.more_layers.x, positive);
        receiver.layer = select(select(z_layer, y_layer, y_major), x_layer, x_major);
    }
    var across = receiver.q.xy;
    if (!orthographic) {
        across = across / max(-receiver.q.z, light.depth.x);
    }
    receiver.sample = across * light.texels.xy + light.texels.zw;
    return receiver;
}

// A vector of the cube frame in the view of a face (+X, −X, +Y, −Y, +Z, −Z: the major axis
// and its sign): the rows of that face's rotation (render/passes/shadow_views.py
// face_rotation; tests/test_shadow_views.py checks the two agree). With s = ±1 the sign:
// +X/−X (−s·z, −y, −s·x), +Y/−Y (x, s·z, −s·y), +Z/−Z (s·x, −y, −s·z).
fn cube_face_turn(c: vec3<f32>, x_major: bool, y_major: bool, positive: bool) -> vec3<f32> {
    let s = select(-1.0, 1.0, positive);
    let x_face = vec3<f32>(-s * c.z, -c.y, -s * c.x);
    let y_face = vec3<f32>(c.x, s * c.z, -s * c.y);
    let z_face = vec3<f32>(s * c.x, -c.y, -s * c.z);
    return select(select(z_face, y_face, y_major), x_face, x_major);
}

// The reversed depth key of the receiver on the ray through texel centre `texel`, moved
// the bias towards the light: a stored key above it is a caster in front of the receiver.
// The receiver there is its triangle's plane, but never farther than its own point: where
// that plane dives behind another surface within a texel (a triangle edge-on to the light
// next to a contact), that surface is not in front of the point itself.
fn plane_key(light: ShadowLight, receiver: ShadowReceiver, texel: vec2<f32>, orthographic: bool) -> f32 {
    let own = -receiver.q.z;  // t: distance along the view's axis
    if (orthographic) {
        // The plane's t changes by n.xy / n.z per unit of x and y across the light.
        let facing = select(-1.0, 1.0, receiver.n.z >= 0.0) * max(abs(receiver.n.z), 1.0 / MAX_SHADOW_SLOPE);
        let offset = (texel - receiver.sample) / light.texels.xy;
        let t = min(own + dot(receiver.n.xy, offset) / facing, own) - light.depth.y;
        return max(1.0 - t * light.depth.x, 0.0);
    }
    // The ray from the light through the texel centre, t · (x/t, y/t, −1), meets the plane
    // n·(p − q) = 0 at t = n·q / n·ray: used where that is in front of the light and not
    // beyond MAX_SHADOW_SLOPE times the point's own distance.
    let ray = vec3<f32>((texel - light.texels.zw) / light.texels.xy, -1.0);
    let towards = dot(receiver.n, ray);
    let crossing = dot(receiver.n, receiver.q);
    var t = own;
    if (crossing * towards > 0.0 && abs(crossing) < abs(towards) * MAX_SHADOW_SLOPE * max(own, light.depth.x)) {
        t = min(crossing / towards, own);
    }
    return light.depth.x / max(t * (1.0 - light.depth.y), light.depth.x * 1e-6);
}

#if SHADOW_FILTER_NEAREST
// The nearest texel, compared with the receiver's plane at that texel's centre (exact for
// a plane however it faces the light).
fn filtered_visibility(light: ShadowLight, receiver: ShadowReceiver, orthographic: bool) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let texel = clamp(floor(receiver.sample), vec2<f32>(0.0), size - 1.0);
    let stored = textureLoad(shadow_maps, vec2<i32>(texel), receiver.layer, 0);
    return step(stored, plane_key(light, receiver, texel + 0.5, orthographic));
}
#else
// One bilinear comparison at `at` (texel coordinates): the comparison sampler weighs the
// four texels around it; their one reference is the receiver's plane at the nearest of
// their four centres (the receiver then meets itself in all four).
fn compared_tap(light: ShadowLight, receiver: ShadowReceiver, at: vec2<f32>, size: vec2<f32>, orthographic: bool) -> f32 {
    let first = floor(at - 0.5) + 0.5;
    let key = max(
        max(plane_key(light, receiver, first, orthographic), plane_key(light, receiver, first + vec2<f32>(1.0, 0.0), orthographic)),
        max(plane_key(light, receiver, first + vec2<f32>(0.0, 1.0), orthographic), plane_key(light, receiver, first + 1.0, orthographic)),
    );
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, at / size, receiver.layer, key);
}

// SHADOW_FILTER_RADIUS 0: one bilinear comparison; 1, 2: the mean of a 3×3 or 5×5 grid of
// them, one texel apart (percentage-closer filtering; deterministic).
fn filtered_visibility(light: ShadowLight, receiver: ShadowReceiver, orthographic: bool) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    var sum = 0.0;
    for (var row = -SHADOW_FILTER_RADIUS; row <= SHADOW_FILTER_RADIUS; row++) {
        for (var column = -SHADOW_FILTER_RADIUS; column <= SHADOW_FILTER_RADIUS; column++) {
            sum += compared_tap(light, receiver, receiver.sample + vec2<f32>(f32(column), f32(row)), size, orthographic);
        }
    }
    let side = f32(2 * SHADOW_FILTER_RADIUS + 1);
    return sum / (side * side);
}
#endif

// V of casting light `slot` at this fragment (slots: directional lights, then spot, then
// positional lights; render/features.py casting_lights).
fn shadow_visibility(slot: u32) -> f32 {
    let light = shadow_uniforms.lights[slot];
    let orthographic = slot < DIRECTIONAL_SHADOW_COUNT;
    let receiver = shadow_receiver(light, slot, orthographic);
    if (receiver.layer < 0) {
        return 1.0;
    }
    // A closed surface's point facing away from the light: the segment towards it enters the
    // solid and must leave it through the surface — exact, whatever the map's resolution
    // tells about a triangle nearly edge-on to the light (docs/shadows.md#closed-surfaces).
    let self_shadowing = slot < 32u && ((object_uniforms.self_shadowing_lights >> slot) & 1u) != 0u;
    let towards_light = select(dot(receiver.n, -receiver.q), receiver.n.z, orthographic);
    if (self_shadowing && outward_known && towards_light < 0.0) {
        return 0.0;
    }
    // The window holds every visible receiver a caster can shadow: outside it, lit.
    let size = vec2<f32>(textureDimensions(shadow_maps));
    if (any(receiver.sample < vec2<f32>(0.0)) || any(receiver.sample > size)) {
        return 1.0;
    }
    return filtered_visibility(light, receiver, orthographic);
}
#endif
