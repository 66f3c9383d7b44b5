//! The node library, one module per family. Each node type keeps its declaration, CPU
//! compute and hard cases together; [`all()`](crate::nodes::all) lists them for the registry.

pub mod blender_brick;
pub mod blender_magic;
pub mod blender_noise;
pub mod blender_voronoi;
pub mod blender_wave;
pub mod bubble;
pub mod bump;
pub mod color_ramp;
pub mod curves;
pub mod ibl;
pub mod image;
pub mod input;
pub mod mapping;
pub mod math;
pub mod math_scalar;
pub mod math_vector;
pub mod normal_map;
pub mod optics;
pub mod pbr;
pub mod precise;
pub mod skin;
pub mod sunshine;
pub mod texture;
pub mod texture_coordinate;
pub mod thin_film;
pub mod toon_water;
pub mod transmission;
pub mod triplanar;
pub mod wide;

use crate::node::NodeType;

/// Every node type shipped with matgraph, in menu order.
pub fn all() -> Vec<NodeType> {
    let mut v = Vec::new();
    v.extend(input::all());
    v.extend(math::all());
    v.extend(math_scalar::all());
    v.extend(math_vector::all());
    v.extend(optics::all());
    v.extend(thin_film::all());
    v.extend(skin::all());
    v.extend(pbr::all());
    v.extend(transmission::all());
    v.extend(ibl::all());
    v.extend(bubble::all());
    v.extend(texture::all());
    v.extend(image::all());
    v.extend(sunshine::all());
    v.extend(toon_water::all());
    // Last: the parity suites seed each type's random samples by its index in this list,
    // so types added at the end leave every earlier type's samples where they were.
    v.extend(blender_noise::all());
    v.extend(blender_voronoi::all());
    v.extend(mapping::all());
    v.extend(normal_map::all());
    v.extend(blender_wave::all());
    v.extend(blender_brick::all());
    v.extend(blender_magic::all());
    v.extend(triplanar::all());
    v.extend(texture_coordinate::all());
    v.push(color_ramp::color_ramp_type());
    v.push(curves::float_curve_type());
    v.push(curves::rgb_curves_type());
    v.extend(bump::all());
    v
}
