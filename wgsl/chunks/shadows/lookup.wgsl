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

// The receiver at this fragment, in eye space: its point and its triangle's outward unit
// normal (the side its winding calls front).
var<private> shadow_receiver_position: vec3<f32>;
var<private> shadow_receiver_normal: vec3<f32>;

// Called first thing by the fragment stage (screen derivatives need uniform control flow).
// The derivatives of the interpolated position lie in the fragment's own triangle, so their
// cross product is the triangle's normal at every shading frequency; framebuffer y points
// down, so −(∂p/∂x × ∂p/∂y) points to the side the camera sees.
fn prepare_shadows(eye_position: vec3<f32>, front_facing: bool) {
    let across = safe_normalize(dpdx(eye_position), vec3<f32>(1.0, 0.0, 0.0));
    let down = safe_normalize(dpdy(eye_position), vec3<f32>(0.0, 1.0, 0.0));
    let seen_side = -safe_normalize(cross(across, down), FALLBACK_NORMAL);
    shadow_receiver_position = eye_position;
    shadow_receiver_normal = select(-seen_side, seen_side, front_facing) * object_uniforms.outward_sign;
}

// The steepest plane the comparison extends, in distance per unit across the light: an
// edge-on triangle is extended at this slope (finite numbers, the same answer).
const MAX_SHADOW_SLOPE: f32 = 1e6;

// The receiver in one view: its point q and outward normal n in the view's space, and where
// the fragment falls in the map (texel coordinates).
struct ShadowReceiver {
    q: vec3<f32>,
    n: vec3<f32>,
    sample: vec2<f32>,
}

fn shadow_receiver(view: ShadowView, orthographic: bool) -> ShadowReceiver {
    var receiver: ShadowReceiver;
    receiver.q = (view.light_from_eye * vec4<f32>(shadow_receiver_position, 1.0)).xyz;
    receiver.n = (view.light_from_eye * vec4<f32>(shadow_receiver_normal, 0.0)).xyz;
    var across = receiver.q.xy;
    if (!orthographic) {
        across = across / max(-receiver.q.z, view.depth.x);
    }
    receiver.sample = across * view.texels.xy + view.texels.zw;
    return receiver;
}

// The reversed depth key of the receiver on the ray through texel centre `texel`, moved
// the bias towards the light: a stored key above it is a caster in front of the receiver.
// The receiver there is its triangle's plane, but never farther than its own point: where
// that plane dives behind another surface within a texel (a triangle edge-on to the light
// next to a contact), that surface is not in front of the point itself.
fn plane_key(view: ShadowView, receiver: ShadowReceiver, texel: vec2<f32>, orthographic: bool) -> f32 {
    let own = -receiver.q.z;  // t: distance along the view's axis
    if (orthographic) {
        // The plane's t changes by n.xy / n.z per unit of x and y across the light.
        let facing = select(-1.0, 1.0, receiver.n.z >= 0.0) * max(abs(receiver.n.z), 1.0 / MAX_SHADOW_SLOPE);
        let offset = (texel - receiver.sample) / view.texels.xy;
        let t = min(own + dot(receiver.n.xy, offset) / facing, own) - view.depth.y;
        return max(1.0 - t * view.depth.x, 0.0);
    }
    // The ray from the light through the texel centre, t · (x/t, y/t, −1), meets the plane
    // n·(p − q) = 0 at t = n·q / n·ray: used where that is in front of the light and not
    // beyond MAX_SHADOW_SLOPE times the point's own distance.
    let ray = vec3<f32>((texel - view.texels.zw) / view.texels.xy, -1.0);
    let towards = dot(receiver.n, ray);
    let crossing = dot(receiver.n, receiver.q);
    var t = own;
    if (crossing * towards > 0.0 && abs(crossing) < abs(towards) * MAX_SHADOW_SLOPE * max(own, view.depth.x)) {
        t = min(crossing / towards, own);
    }
    return view.depth.x / max(t * (1.0 - view.depth.y), view.depth.x * 1e-6);
}

#if SHADOW_FILTER_NEAREST
// The nearest texel, compared with the receiver's plane at that texel's centre (exact for
// a plane however it faces the light).
fn filtered_visibility(view: ShadowView, receiver: ShadowReceiver, orthographic: bool) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    let texel = clamp(floor(receiver.sample), vec2<f32>(0.0), size - 1.0);
    let stored = textureLoad(shadow_maps, vec2<i32>(texel), view.layer, 0);
    return step(stored, plane_key(view, receiver, texel + 0.5, orthographic));
}
#else
// One bilinear comparison at `at` (texel coordinates): the comparison sampler weighs the
// four texels around it; their one reference is the receiver's plane at the nearest of
// their four centres (the receiver then meets itself in all four).
fn compared_tap(view: ShadowView, receiver: ShadowReceiver, at: vec2<f32>, size: vec2<f32>, orthographic: bool) -> f32 {
    let first = floor(at - 0.5) + 0.5;
    let key = max(
        max(plane_key(view, receiver, first, orthographic), plane_key(view, receiver, first + vec2<f32>(1.0, 0.0), orthographic)),
        max(plane_key(view, receiver, first + vec2<f32>(0.0, 1.0), orthographic), plane_key(view, receiver, first + 1.0, orthographic)),
    );
    return textureSampleCompareLevel(shadow_maps, shadow_sampler, at / size, view.layer, key);
}

// SHADOW_FILTER_RADIUS 0: one bilinear comparison; 1, 2: the mean of a 3×3 or 5×5 grid of
// them, one texel apart (percentage-closer filtering; deterministic).
fn filtered_visibility(view: ShadowView, receiver: ShadowReceiver, orthographic: bool) -> f32 {
    let size = vec2<f32>(textureDimensions(shadow_maps));
    var sum = 0.0;
    for (var row = -SHADOW_FILTER_RADIUS; row <= SHADOW_FILTER_RADIUS; row++) {
        for (var column = -SHADOW_FILTER_RADIUS; column <= SHADOW_FILTER_RADIUS; column++) {
            sum += compared_tap(view, receiver, receiver.sample + vec2<f32>(f32(column), f32(row)), size, orthographic);
        }
    }
    let side = f32(2 * SHADOW_FILTER_RADIUS + 1);
    return sum / (side * side);
}
#endif

// V of one view at the fragment (-1: no view, lit). `self_shadowing`: the receiver is a
// closed surface that hides this light from its own points facing away from it.
fn view_visibility(view_index: i32, orthographic: bool, self_shadowing: bool) -> f32 {
    if (view_index < 0) {
        return 1.0;
    }
    let view = shadow_uniforms.views[view_index];
    let receiver = shadow_receiver(view, orthographic);
    // The segment towards the light enters the solid and must leave it through the surface:
    // exact, whatever the map's resolution tells about a triangle nearly edge-on to the light.
    let towards_light = select(dot(receiver.n, -receiver.q), receiver.n.z, orthographic);
    if (self_shadowing && towards_light < 0.0) {
        return 0.0;
    }
    // The window holds every visible receiver a caster can shadow: outside it, lit.
    let size = vec2<f32>(textureDimensions(shadow_maps));
    if (any(receiver.sample < vec2<f32>(0.0)) || any(receiver.sample > size)) {
        return 1.0;
    }
    return filtered_visibility(view, receiver, orthographic);
}

// The view of the cube face a point falls in, by the largest axis of its direction from the
// light (+X, −X, +Y, −Y, +Z, −Z). Each face reaches a guard band past its edges, so a point
// near an edge finds every texel its filter reads in that one face.
fn cube_view(light: ShadowLight) -> i32 {
    let direction = (light.cube_from_eye * vec4<f32>(shadow_receiver_position, 1.0)).xyz;
    let size = abs(direction);
    if (size.x >= size.y && size.x >= size.z) {
        return select(light.views.y, light.views.x, direction.x >= 0.0);
    }
    if (size.y >= size.z) {
        return select(light.views.w, light.views.z, direction.y >= 0.0);
    }
    return select(light.more_views.y, light.more_views.x, direction.z >= 0.0);
}

// V of casting light `slot` at this fragment (slots: directional lights, then spot, then
// positional lights; render/features.py casting_lights).
fn shadow_visibility(slot: u32) -> f32 {
    let light = shadow_uniforms.lights[slot];
    let self_shadowing = slot < 32u && ((object_uniforms.self_shadowing_lights >> slot) & 1u) != 0u;
    if (slot < DIRECTIONAL_SHADOW_COUNT) {
        return view_visibility(light.views.x, true, self_shadowing);
    }
    if (light.more_views.z == 0) {
        return view_visibility(light.views.x, false, self_shadowing);
    }
    return view_visibility(cube_view(light), false, self_shadowing);
}
#endif
