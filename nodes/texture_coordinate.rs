//! Blender's Texture Coordinate node: the coordinates a texture is placed by, as geometry
//! attributes the renderer supplies.
//!
//! Source: Blender 4.x Texture Coordinate (`node_shader_tex_coord.cc`; Cycles
//! `svm_node_tex_coord` in intern/cycles/kernel/svm/tex_coord.h; EEVEE `node_tex_coord`).
//! Deviations, each stated on its port: `uv` is matgraph's two-component uv (Blender's has a
//! third component, 0); `object` is the world position (matgraph's meshes are built in world
//! space, with no object transform); `generated` is the position in the bounding box of the
//! material surface as built (Blender interpolates the undisplaced coordinates, ours follow a
//! displaced surface); `window` follows the pixel's sample, not Blender's unjittered camera ray.

use crate::node::{Attribute, Category, NodeType, Out};
use glam::{Vec2, Vec3};

/// The texture coordinate node type.
pub fn all() -> Vec<NodeType> {
    use Attribute::*;
    vec![
        NodeType::new(
            "texture_coordinate",
            Category::Geometry,
            "Blender's Texture Coordinate: uv, object, world, generated, reflection, window and camera coordinates.",
        )
        .source(
            "Blender 4.x Texture Coordinate (Cycles svm_node_tex_coord, EEVEE node_tex_coord). \
             uv: the mesh's uv (two components; Blender's third is 0). object: the position in \
             object space, which is world space here (meshes are built in world space). world: \
             the world position. generated: 0.5 + (p − c) / (2 h) per axis in the material \
             surface's box (centre c, half size h: the sphere's c ± r, the water plane's size; \
             a flat axis's h is 1 and h ≥ 10⁻⁵, as Blender's BKE_mesh_texspace_calc), so the \
             box spans [0, 1]³ (of the displaced position: Blender uses the undisplaced one). \
             reflection: 2 (N · V) N − V, the view mirrored about the normal, world space. \
             window: (x, 1 − y, 0) of screen_uv, (0, 0) at the bottom left, (1, 1) top right \
             (Blender's). camera: the position in the camera's frame, x right, y up, z forward \
             (positive in front of the eye; Cycles' camera space; EEVEE's flips to the same), \
             metres. Without a scene (matgraph eval): uv and window (½, ½[, 0]), object and \
             world the origin, generated (½, ½, ½), reflection +z, camera (0, 0, 1).",
        )
        .output(Out::vec2("uv").doc("The surface's texture coordinates."))
        .output(Out::vec3("object").unit("m").doc("Object-space position (= world: meshes are built in world space)."))
        .output(Out::vec3("world").unit("m").doc("World-space position."))
        .output(Out::vec3("generated").doc("Position in the surface's bounding box, [0, 1] per axis."))
        .output(Out::vec3("reflection").doc("The view direction mirrored about the normal, 2 (N · V) N − V."))
        .output(Out::vec3("window").doc("Screen position, (0, 0) bottom left to (1, 1) top right, z 0."))
        .output(Out::vec3("camera").unit("m").doc("Position in camera space: x right, y up, z forward (> 0 in front)."))
        .attributes(&[Uv, Position, Position, Generated, Reflection, Window, Camera])
        .compute(|| {
            (
                Vec2::splat(0.5),
                Vec3::ZERO,
                Vec3::ZERO,
                Vec3::splat(0.5),
                Vec3::Z,
                Vec3::new(0.5, 0.5, 0.0),
                Vec3::Z,
            )
        }),
    ]
}
