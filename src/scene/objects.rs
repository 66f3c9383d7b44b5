//! The scene's built-in (non-material) geometry: meshes with their albedo for built-in
//! shading, and analytic shapes that cast shadows.

use glam::{Vec2, Vec3, Vec4};
use std::sync::Arc;

use super::Scene;
use super::bubble::BackdropShader;
use super::kind::{SceneKind, WaterObject};
use super::mesh::Mesh;

/// Albedo of a built-in surface.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Albedo {
    /// One colour.
    Constant(Vec3),
    /// A checker in the plane spanned by unit axes `u` and `v`: colour `colors[k]` with
    /// `k = (floor(p·u / size) + floor(p·v' / size)) mod 2`, `v' = v` measured from `v0`.
    Checker {
        u: Vec3,
        v: Vec3,
        v0: f32,
        size: f32,
        colors: [Vec3; 2],
    },
    /// No albedo: an unlit surface with radiance of its own (the bubble scene's backdrop),
    /// which built-in shading returns as it is.
    Unlit(Arc<BackdropShader>),
}

impl Albedo {
    /// The albedo at world point `p`.
    #[inline]
    pub(crate) fn at(&self, p: Vec3) -> Vec3 {
        match *self {
            Albedo::Constant(c) => c,
            Albedo::Checker {
                u,
                v,
                v0,
                size,
                colors,
            } => {
                let a = floor_i64(p.dot(u) / size);
                let b = floor_i64((p.dot(v) - v0) / size);
                colors[(a + b).rem_euclid(2) as usize]
            }
            Albedo::Unlit(_) => Vec3::ONE,
        }
    }
}

/// `floor(x)` as an integer without a libm call (saturating for huge values).
#[inline]
fn floor_i64(x: f32) -> i64 {
    let i = x as i64;
    if (i as f32) > x { i - 1 } else { i }
}

/// A built-in surface.
#[derive(Clone, Debug)]
pub(crate) struct Object {
    /// Its triangles, world space.
    pub mesh: Mesh,
    /// Its albedo.
    pub albedo: Albedo,
    /// Whether it lies wholly below the water plane (left out of the reflection pass).
    pub underwater: bool,
    /// Its own entry in [`Geometry::casters`], skipped when shading it (a convex object
    /// does not shadow itself beyond `N·L`, and its facets lie inside its analytic shape).
    pub caster: Option<usize>,
}

/// An analytic shadow caster. Ray tests: the sphere by its quadratic, the box by the slab
/// method (Kay and Kajiya, "Ray tracing complex scenes", SIGGRAPH 1986), the cylinder by
/// the quadratic of its side in the xz plane plus its two cap discs (Shirley and Marschner,
/// "Fundamentals of Computer Graphics", ray–object intersection).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    Aabb {
        min: Vec3,
        max: Vec3,
    },
    /// A vertical cylinder with caps.
    Cylinder {
        x: f32,
        z: f32,
        radius: f32,
        y0: f32,
        y1: f32,
    },
}

impl Shape {
    /// Whether the ray `o + t d` (unit `d`) meets the shape for some `t` in `(0, t_max)`.
    #[inline]
    pub(crate) fn occludes(&self, o: Vec3, d: Vec3, t_max: f32) -> bool {
        let within = |t: f32| t > 0.0 && t < t_max;
        match *self {
            Shape::Sphere { center, radius } => {
                let oc = o - center;
                let b = oc.dot(d);
                let c = oc.length_squared() - radius * radius;
                if c > 0.0 && b > 0.0 {
                    // Outside and heading away.
                    return false;
                }
                let disc = b * b - c;
                if disc < 0.0 {
                    return false;
                }
                let s = disc.sqrt();
                within(-b - s) || within(-b + s)
            }
            Shape::Aabb { min, max } => {
                let inv = d.recip();
                let t0 = (min - o) * inv;
                let t1 = (max - o) * inv;
                let near = t0.min(t1).max_element();
                let far = t0.max(t1).min_element();
                // NaN (a zero direction component on a slab boundary) reads as a miss.
                far >= near.max(0.0) && near < t_max && far > 0.0
            }
            Shape::Cylinder {
                x,
                z,
                radius,
                y0,
                y1,
            } => {
                let (ox, oz) = (o.x - x, o.z - z);
                let a = d.x * d.x + d.z * d.z;
                if a > 1e-12 {
                    let b = ox * d.x + oz * d.z;
                    let c = ox * ox + oz * oz - radius * radius;
                    let disc = b * b - a * c;
                    if disc >= 0.0 {
                        let s = disc.sqrt();
                        for t in [(-b - s) / a, (-b + s) / a] {
                            let y = o.y + t * d.y;
                            if within(t) && y >= y0 && y <= y1 {
                                return true;
                            }
                        }
                    }
                }
                if d.y.abs() > 1e-12 {
                    for y in [y0, y1] {
                        let t = (y - o.y) / d.y;
                        let (px, pz) = (ox + t * d.x, oz + t * d.z);
                        if within(t) && px * px + pz * pz <= radius * radius {
                            return true;
                        }
                    }
                }
                false
            }
        }
    }
}

/// The built-in geometry of a scene.
#[derive(Clone, Debug)]
pub(crate) struct Geometry {
    /// Built-in surfaces, in drawing order.
    pub objects: Vec<Object>,
    /// Shadow casters other than the material surface.
    pub casters: Vec<Shape>,
    /// The material surface as a shadow caster for built-in surfaces (the undisplaced ball;
    /// none for water, which lets light through).
    pub material_caster: Option<Shape>,
}

/// The world plane `y = 0` keeping `y ≤ 0` (below the water), as `(n, d)` with `n·p + d ≥ 0`.
pub(crate) const BELOW_WATER: Vec4 = Vec4::new(0.0, -1.0, 0.0, 0.0);
/// The world plane `y = 0` keeping `y ≥ 0` (above the water).
pub(crate) const ABOVE_WATER: Vec4 = Vec4::new(0.0, 1.0, 0.0, 0.0);

/// The ball's surface as a shadow caster: the sphere, or the card as a box 2 % of its side
/// deep behind its face (so the floor and wall behind it are shadowed, and the face's own
/// shadow rays, which leave forwards, miss it).
fn ball_caster(ball: &super::BallSetup) -> Shape {
    let (c, r) = (Vec3::from(ball.center), ball.radius);
    match ball.shape {
        super::BallShape::Sphere => Shape::Sphere {
            center: c,
            radius: r,
        },
        super::BallShape::Plane => Shape::Aabb {
            min: c - Vec3::new(r, r, 0.04 * r),
            max: c + Vec3::new(r, r, 0.0),
        },
    }
}

impl Scene {
    /// The scene's built-in meshes and shadow casters.
    pub(crate) fn geometry(&self) -> Geometry {
        match &self.kind {
            SceneKind::Ball(ball) => {
                let mut objects = Vec::new();
                let b = &ball.backdrop;
                if b.enabled {
                    let colors = b.colors.map(Vec3::from);
                    let x0 = -0.5 * b.width;
                    let floor = Mesh::parallelogram(
                        Vec3::new(x0, b.floor_y, b.wall_z + b.floor_depth),
                        Vec3::new(b.width, 0.0, 0.0),
                        Vec3::new(0.0, 0.0, -b.floor_depth),
                        [1, 1],
                    );
                    let wall = Mesh::parallelogram(
                        Vec3::new(x0, b.floor_y, b.wall_z),
                        Vec3::new(b.width, 0.0, 0.0),
                        Vec3::new(0.0, b.wall_height, 0.0),
                        [1, 1],
                    );
                    objects.push(Object {
                        mesh: floor,
                        albedo: Albedo::Checker {
                            u: Vec3::X,
                            v: Vec3::Z,
                            v0: 0.0,
                            size: b.checker_size,
                            colors,
                        },
                        underwater: false,
                        caster: None,
                    });
                    objects.push(Object {
                        mesh: wall,
                        albedo: Albedo::Checker {
                            u: Vec3::X,
                            v: Vec3::Y,
                            v0: b.floor_y,
                            size: b.checker_size,
                            colors,
                        },
                        underwater: false,
                        caster: None,
                    });
                }
                Geometry {
                    objects,
                    casters: Vec::new(),
                    material_caster: Some(ball_caster(ball)),
                }
            }
            SceneKind::Bubble(bubble) => super::bubble::geometry(bubble, self.time),
            SceneKind::Water(water) => {
                let [sx, sz] = water.size;
                let sand = Albedo::Constant(Vec3::from(water.seabed.color));
                let mut objects = vec![Object {
                    mesh: Mesh::heightfield(
                        Vec2::ZERO,
                        Vec2::new(sx, sz),
                        water.seabed.grid,
                        |x, z| water.seabed_height(x, z),
                    ),
                    albedo: sand.clone(),
                    underwater: true,
                    caster: None,
                }];
                // Skirts from the water line down past the deepest seabed, facing inwards.
                let bottom = -(water.seabed.depth_max + 1.0);
                let (hx, hz) = (0.5 * sx, 0.5 * sz);
                let down = Vec3::new(0.0, bottom, 0.0);
                let mut skirts = Mesh::default();
                for (corner, along) in [
                    (Vec3::new(-hx, 0.0, -hz), Vec3::new(sx, 0.0, 0.0)),
                    (Vec3::new(hx, 0.0, -hz), Vec3::new(0.0, 0.0, sz)),
                    (Vec3::new(hx, 0.0, hz), Vec3::new(-sx, 0.0, 0.0)),
                    (Vec3::new(-hx, 0.0, hz), Vec3::new(0.0, 0.0, -sz)),
                ] {
                    // cross(down, along) points into the pool for this corner order.
                    skirts.append(&Mesh::parallelogram(corner, down, along, [1, 1]));
                }
                objects.push(Object {
                    mesh: skirts,
                    albedo: sand,
                    underwater: true,
                    caster: None,
                });
                let mut casters = Vec::new();
                for obj in &water.objects {
                    let (mesh, shape, underwater) = match obj {
                        WaterObject::Box(b) => {
                            let (c, s) = (Vec3::from(b.center), Vec3::from(b.size));
                            (
                                Mesh::cuboid(c, s),
                                Shape::Aabb {
                                    min: c - 0.5 * s,
                                    max: c + 0.5 * s,
                                },
                                c.y + 0.5 * s.y <= 0.0,
                            )
                        }
                        WaterObject::Sphere(s) => {
                            let c = Vec3::from(s.center);
                            (
                                Mesh::uv_sphere(c, s.radius, 48, 24),
                                Shape::Sphere {
                                    center: c,
                                    radius: s.radius,
                                },
                                c.y + s.radius <= 0.0,
                            )
                        }
                        WaterObject::Pole(p) => (
                            Mesh::cylinder(
                                Vec3::new(p.base[0], p.bottom, p.base[1]),
                                p.top - p.bottom,
                                p.radius,
                                24,
                            ),
                            Shape::Cylinder {
                                x: p.base[0],
                                z: p.base[1],
                                radius: p.radius,
                                y0: p.bottom,
                                y1: p.top,
                            },
                            p.top <= 0.0,
                        ),
                    };
                    objects.push(Object {
                        mesh,
                        albedo: Albedo::Constant(obj.color()),
                        underwater,
                        caster: Some(casters.len()),
                    });
                    casters.push(shape);
                }
                Geometry {
                    objects,
                    casters,
                    material_caster: None,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_occlude_only_between_origin_and_light() {
        let shapes = [
            Shape::Sphere {
                center: Vec3::new(0.0, 2.0, 0.0),
                radius: 0.5,
            },
            Shape::Aabb {
                min: Vec3::new(-0.5, 1.5, -0.5),
                max: Vec3::new(0.5, 2.5, 0.5),
            },
            Shape::Cylinder {
                x: 0.0,
                z: 0.0,
                radius: 0.5,
                y0: 1.5,
                y1: 2.5,
            },
        ];
        for s in shapes {
            assert!(
                s.occludes(Vec3::ZERO, Vec3::Y, f32::INFINITY),
                "{s:?} above"
            );
            assert!(
                !s.occludes(Vec3::ZERO, Vec3::Y, 1.0),
                "{s:?} beyond the light"
            );
            assert!(
                !s.occludes(Vec3::ZERO, Vec3::NEG_Y, f32::INFINITY),
                "{s:?} behind"
            );
            assert!(
                !s.occludes(Vec3::new(2.0, 0.0, 0.0), Vec3::Y, f32::INFINITY),
                "{s:?} beside"
            );
            let slant = Vec3::new(1.0, 4.0, 0.0).normalize();
            assert!(
                s.occludes(Vec3::new(-0.4, 0.0, 0.0), slant, f32::INFINITY),
                "{s:?} slant"
            );
        }
        // The cylinder's side, from beside it.
        let pole = shapes[2];
        assert!(pole.occludes(Vec3::new(3.0, 2.0, 0.0), Vec3::NEG_X, f32::INFINITY));
        assert!(!pole.occludes(Vec3::new(3.0, 3.0, 0.0), Vec3::NEG_X, f32::INFINITY));
    }

    #[test]
    fn checker_alternates_per_square() {
        let a = Albedo::Checker {
            u: Vec3::X,
            v: Vec3::Z,
            v0: 0.0,
            size: 0.5,
            colors: [Vec3::ONE, Vec3::ZERO],
        };
        assert_eq!(a.at(Vec3::new(0.25, 0.0, 0.25)), Vec3::ONE);
        assert_eq!(a.at(Vec3::new(0.75, 0.0, 0.25)), Vec3::ZERO);
        assert_eq!(a.at(Vec3::new(-0.25, 0.0, 0.25)), Vec3::ZERO);
        assert_eq!(a.at(Vec3::new(-0.25, 0.0, -0.25)), Vec3::ONE);
        assert_eq!(floor_i64(-0.5), -1);
        assert_eq!(floor_i64(2.0), 2);
    }
}
