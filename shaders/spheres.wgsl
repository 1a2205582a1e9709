// The spheres read by index from a storage buffer: appended to `scene.wgsl` where the
// GPU lets vertex shaders read storage buffers. One plain draw of 3n vertices draws n
// spheres, not n instances: a software GPU (lavapipe) runs its whole vertex pipeline
// once per instance, which at 100,000 spheres cost more than the shading.

@group(0) @binding(1) var<storage, read> spheres: array<Sphere>;

@vertex
fn vs_sphere(@builtin(vertex_index) index: u32) -> SphereOut {
    return sphere_vertex(spheres[index / 3u], index % 3u);
}

@vertex
fn vs_shadow(@builtin(vertex_index) index: u32) -> ShadowOut {
    return shadow_vertex(spheres[index / 3u], index % 3u);
}
