//! The stops of a `color_ramp` and the points of a `float_curve` or `rgb_curves` as the
//! editor's ramp-and-curve widget edits them ([`super::ramp_ui`]): read from the node's
//! literals (or its defaults), and each edit (move, add, remove, recolour) as the inputs it
//! writes. A stop or point is inputs of its own (`pos_k`/`color_k`, `point_k`, `c_k`…) with
//! a count, so removing one shifts those after it down, as Blender's list does.

use super::model::EditorDoc;
use super::widgets::current_lanes;
use crate::nodes::color_ramp::{self, Stop};
use crate::nodes::curves::{self, Curve};
use crate::types::SocketType;
use crate::value::json_f32;
use glam::{Vec2, Vec4};
use serde_json::{Value as J, json};

/// The node types the widget edits, and how many of their first inputs keep their pins
/// (the rest, stops or points and their counts, are the widget's).
pub const PINNED: [(&str, usize); 3] = [("color_ramp", 2), ("float_curve", 3), ("rgb_curves", 3)];

/// The inputs one edit writes: (input name, literal).
pub type Edits = Vec<(String, J)>;

/// How many of the first inputs of a node of type `ty` keep their pins; `None` for a type
/// without the widget.
pub fn pinned(ty: &str) -> Option<usize> {
    PINNED.iter().find(|(t, _)| *t == ty).map(|(_, n)| *n)
}

/// Input `name` of node `id` as lanes (its literal, or its default).
fn lanes(doc: &EditorDoc, id: &str, name: &str) -> Option<Vec<f32>> {
    let decl = doc.ports(id)?.inputs.iter().find(|p| p.name == name)?;
    let ty = doc.port_type(id, decl.ty).unwrap_or(SocketType::Float);
    let written = doc.node(id)?.inputs.get(name);
    let default = decl.default_for(SocketType::Float);
    Some(current_lanes(decl, ty, written, &default))
}

/// A ramp's stops, in input order (not sorted), and its interpolation.
#[derive(Clone, Debug, PartialEq)]
pub struct Ramp {
    /// (position, RGBA) of stops 0 … count − 1.
    pub stops: Vec<(f32, [f32; 4])>,
    /// The interpolation's index in [`color_ramp::INTERPOLATIONS`].
    pub interpolation: i32,
}

impl Ramp {
    /// The ramp of `color_ramp` node `id`.
    pub fn read(doc: &EditorDoc, id: &str) -> Option<Ramp> {
        let count = lanes(doc, id, "count")?[0] as usize;
        let count = count.clamp(1, color_ramp::MAX_STOPS);
        let stops = (0..count)
            .map(|k| {
                let p = lanes(doc, id, color_ramp::POSITIONS[k]).map_or(0.0, |l| l[0]);
                let c = lanes(doc, id, color_ramp::COLORS[k]).unwrap_or(vec![0.0; 4]);
                (p, [c[0], c[1], c[2], c[3]])
            })
            .collect();
        let interpolation = lanes(doc, id, "interpolation")?[0] as i32;
        Some(Ramp {
            stops,
            interpolation,
        })
    }

    /// The ramp's colour at `fac` (the node's own evaluation).
    pub fn at(&self, fac: f32) -> [f32; 4] {
        let stops: Vec<Stop> = self
            .stops
            .iter()
            .map(|&(pos, c)| Stop {
                pos,
                color: Vec4::from_array(c),
            })
            .collect();
        color_ramp::color_ramp(&stops, stops.len() as i32, fac, self.interpolation).to_array()
    }

    /// Stop `k` moved to `pos` (clamped to [0, 1]).
    pub fn move_stop(&self, k: usize, pos: f32) -> Edits {
        vec![(
            color_ramp::POSITIONS[k].to_owned(),
            json_f32(pos.clamp(0.0, 1.0)),
        )]
    }

    /// Stop `k` recoloured.
    pub fn set_color(&self, k: usize, c: [f32; 4]) -> Edits {
        vec![(color_ramp::COLORS[k].to_owned(), rgba(c))]
    }

    /// A stop added at `pos` with the ramp's colour there (Blender's), as the last stop;
    /// `None` when the ramp has 16.
    pub fn add_stop(&self, pos: f32) -> Option<Edits> {
        let k = self.stops.len();
        if k >= color_ramp::MAX_STOPS {
            return None;
        }
        let pos = pos.clamp(0.0, 1.0);
        Some(vec![
            (color_ramp::POSITIONS[k].to_owned(), json_f32(pos)),
            (color_ramp::COLORS[k].to_owned(), rgba(self.at(pos))),
            ("count".to_owned(), json!(k + 1)),
        ])
    }

    /// Stop `k` removed, the later ones shifted down; `None` for the last one left.
    pub fn remove_stop(&self, k: usize) -> Option<Edits> {
        if self.stops.len() <= 1 || k >= self.stops.len() {
            return None;
        }
        let mut e = Edits::new();
        for j in k..self.stops.len() - 1 {
            let (p, c) = self.stops[j + 1];
            e.push((color_ramp::POSITIONS[j].to_owned(), json_f32(p)));
            e.push((color_ramp::COLORS[j].to_owned(), rgba(c)));
        }
        e.push(("count".to_owned(), json!(self.stops.len() - 1)));
        Some(e)
    }
}

/// An RGBA literal.
fn rgba(c: [f32; 4]) -> J {
    J::Array(c.iter().map(|&x| json_f32(x)).collect())
}

/// A point literal.
fn xy(p: [f32; 2]) -> J {
    J::Array(p.iter().map(|&x| json_f32(x)).collect())
}

/// One curve of a node: its count input and point inputs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Channel {
    /// Its tab's label (`C`, `R`, `G`, `B`; empty for a float curve's one curve).
    pub label: &'static str,
    /// Its count input.
    pub count: &'static str,
    /// Its point inputs.
    pub points: &'static [&'static str; curves::MAX_POINTS],
}

/// The curves of a node of type `ty`, in tab order.
pub fn channels(ty: &str) -> Vec<Channel> {
    match ty {
        "float_curve" => vec![Channel {
            label: "",
            count: "count",
            points: &curves::POINTS,
        }],
        "rgb_curves" => ["C", "R", "G", "B"]
            .iter()
            .zip(&curves::RGB_CURVES)
            .map(|(label, (count, points))| Channel {
                label,
                count,
                points,
            })
            .collect(),
        _ => Vec::new(),
    }
}

/// A curve's points, in input order (not sorted).
#[derive(Clone, Debug, PartialEq)]
pub struct CurvePoints {
    /// Which curve.
    pub channel: Channel,
    /// (x, y) of points 0 … count − 1.
    pub points: Vec<[f32; 2]>,
}

impl CurvePoints {
    /// Curve `channel` of node `id`.
    pub fn read(doc: &EditorDoc, id: &str, channel: Channel) -> Option<CurvePoints> {
        let count = lanes(doc, id, channel.count)?[0] as usize;
        let count = count.clamp(curves::MIN_POINTS as usize, curves::MAX_POINTS);
        let points = (0..count)
            .map(|k| {
                let l = lanes(doc, id, channel.points[k]).unwrap_or(vec![0.0; 2]);
                [l[0], l[1]]
            })
            .collect();
        Some(CurvePoints { channel, points })
    }

    /// The curve at `x` over the widget's square (the node's own curve; [0, 1] lies within
    /// its ends, or is drawn flat beyond them).
    pub fn at(&self, x: f32) -> f32 {
        let p: Vec<Vec2> = self.points.iter().map(|&p| Vec2::from_array(p)).collect();
        Curve::new(&p, p.len() as i32).eval(x, false)
    }

    /// Point `k` moved to `p` (clamped to [0, 1]², the widget's square).
    pub fn move_point(&self, k: usize, p: [f32; 2]) -> Edits {
        let p = p.map(|v| v.clamp(0.0, 1.0));
        vec![(self.channel.points[k].to_owned(), xy(p))]
    }

    /// A point added at `p` as the last one; `None` when the curve has 16.
    pub fn add_point(&self, p: [f32; 2]) -> Option<Edits> {
        let k = self.points.len();
        if k >= curves::MAX_POINTS {
            return None;
        }
        let p = p.map(|v| v.clamp(0.0, 1.0));
        Some(vec![
            (self.channel.points[k].to_owned(), xy(p)),
            (self.channel.count.to_owned(), json!(k + 1)),
        ])
    }

    /// Point `k` removed, the later ones shifted down; `None` when two are left (a curve's
    /// fewest).
    pub fn remove_point(&self, k: usize) -> Option<Edits> {
        if self.points.len() <= curves::MIN_POINTS as usize || k >= self.points.len() {
            return None;
        }
        let mut e = Edits::new();
        for j in k..self.points.len() - 1 {
            e.push((self.channel.points[j].to_owned(), xy(self.points[j + 1])));
        }
        e.push((self.channel.count.to_owned(), json!(self.points.len() - 1)));
        Some(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> Ramp {
        Ramp {
            stops: vec![
                (0.0, [0.0, 0.0, 0.0, 1.0]),
                (1.0, [1.0, 1.0, 1.0, 1.0]),
                (0.5, [1.0, 0.0, 0.0, 1.0]),
            ],
            interpolation: color_ramp::LINEAR,
        }
    }

    #[test]
    fn removing_a_stop_shifts_the_later_ones_down() {
        let e = ramp().remove_stop(0).unwrap();
        assert_eq!(
            e,
            vec![
                ("pos_0".to_owned(), json!(1.0)),
                ("color_0".to_owned(), json!([1.0, 1.0, 1.0, 1.0])),
                ("pos_1".to_owned(), json!(0.5)),
                ("color_1".to_owned(), json!([1.0, 0.0, 0.0, 1.0])),
                ("count".to_owned(), json!(2)),
            ]
        );
        let one = Ramp {
            stops: vec![(0.5, [1.0; 4])],
            interpolation: 0,
        };
        assert_eq!(one.remove_stop(0), None);
    }

    #[test]
    fn a_new_stop_takes_the_ramps_colour_there() {
        // Between black at 0 and red at 0.5, a quarter of the way: (0.5, 0, 0), linear.
        let e = ramp().add_stop(0.25).unwrap();
        assert_eq!(e[1], ("color_3".to_owned(), json!([0.5, 0.0, 0.0, 1.0])));
        assert_eq!(e[2], ("count".to_owned(), json!(4)));
    }

    #[test]
    fn a_curve_keeps_two_points_and_clamps_moves_to_its_square() {
        let c = CurvePoints {
            channel: channels("float_curve")[0],
            points: vec![[0.0, 0.0], [1.0, 1.0]],
        };
        assert_eq!(c.remove_point(0), None);
        assert_eq!(
            c.move_point(1, [1.5, -0.25]),
            vec![("point_1".to_owned(), json!([1.0, 0.0]))]
        );
        assert_eq!(channels("rgb_curves")[2].count, "g_count");
    }
}
