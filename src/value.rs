//! Typed constant values: literals in graph files, defaults, parameters and results.

use crate::types::SocketType;
use std::fmt;

/// A value of one [`SocketType`], stored as up to four `f32` lanes.
///
/// Ints and bools are stored in lane 0 as exact floats (ints are exact up to 2^24).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Value {
    ty: SocketType,
    lanes: [f32; 4],
}

impl Value {
    /// A float.
    pub const fn float(x: f32) -> Value {
        Value {
            ty: SocketType::Float,
            lanes: [x, 0.0, 0.0, 0.0],
        }
    }
    /// A vec2.
    pub const fn vec2(v: [f32; 2]) -> Value {
        Value {
            ty: SocketType::Vec2,
            lanes: [v[0], v[1], 0.0, 0.0],
        }
    }
    /// A vec3.
    pub const fn vec3(v: [f32; 3]) -> Value {
        Value {
            ty: SocketType::Vec3,
            lanes: [v[0], v[1], v[2], 0.0],
        }
    }
    /// A vec4.
    pub const fn vec4(v: [f32; 4]) -> Value {
        Value {
            ty: SocketType::Vec4,
            lanes: v,
        }
    }
    /// A linear RGB colour.
    pub const fn color(v: [f32; 3]) -> Value {
        Value {
            ty: SocketType::Color,
            lanes: [v[0], v[1], v[2], 0.0],
        }
    }
    /// An int (or an enum choice index).
    pub const fn int(i: i32) -> Value {
        Value {
            ty: SocketType::Int,
            lanes: [i as f32, 0.0, 0.0, 0.0],
        }
    }
    /// A bool.
    pub const fn boolean(b: bool) -> Value {
        Value {
            ty: SocketType::Bool,
            lanes: [if b { 1.0 } else { 0.0 }, 0.0, 0.0, 0.0],
        }
    }
    /// The zero value of a type (false for bools).
    pub const fn zero(ty: SocketType) -> Value {
        Value {
            ty,
            lanes: [0.0; 4],
        }
    }
    /// Builds a value of type `ty` from its lanes (lanes past the width are ignored).
    pub fn from_lanes(ty: SocketType, lanes: &[f32]) -> Value {
        let mut l = [0.0; 4];
        let w = ty.width().min(lanes.len());
        l[..w].copy_from_slice(&lanes[..w]);
        Value { ty, lanes: l }
    }

    /// The value's type.
    pub const fn ty(&self) -> SocketType {
        self.ty
    }
    /// The lanes that hold the value (as many as the type's width).
    pub fn lanes(&self) -> &[f32] {
        &self.lanes[..self.ty.width()]
    }
    /// All four lanes, zero past the width.
    pub const fn raw(&self) -> [f32; 4] {
        self.lanes
    }
    /// Lane 0 as a float.
    pub const fn as_f32(&self) -> f32 {
        self.lanes[0]
    }
    /// Lane 0 as an int.
    pub fn as_i32(&self) -> i32 {
        self.lanes[0] as i32
    }
    /// Lane 0 as a bool.
    pub fn as_bool(&self) -> bool {
        self.lanes[0] != 0.0
    }
    /// Whether every lane is finite.
    pub fn is_finite(&self) -> bool {
        self.lanes().iter().all(|x| x.is_finite())
    }

    /// Converts along a link from this value's type to `to` (see [`crate::types`]).
    pub fn convert(&self, to: SocketType) -> Option<Value> {
        let c = self.ty.conversion_to(to)?;
        Some(Value {
            ty: to,
            lanes: c.apply(self.lanes, to),
        })
    }

    /// The value as JSON: a number, an array of numbers, or a bool.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::Value as J;
        match self.ty {
            SocketType::Float => json_f32(self.lanes[0]),
            SocketType::Int => J::from(self.as_i32()),
            SocketType::Bool => J::Bool(self.as_bool()),
            _ => J::Array(self.lanes().iter().map(|&x| json_f32(x)).collect()),
        }
    }

    /// Reads a value of type `ty` from JSON; a number is accepted for any vector type
    /// (broadcast), an array must have the type's width. Returns `None` on a mismatch.
    pub fn from_json(ty: SocketType, json: &serde_json::Value) -> Option<Value> {
        use serde_json::Value as J;
        match (ty, json) {
            (SocketType::Bool, J::Bool(b)) => Some(Value::boolean(*b)),
            (SocketType::Int, J::Number(n)) => {
                let i = n.as_i64()?;
                i32::try_from(i).ok().map(Value::int)
            }
            (SocketType::Bool | SocketType::Int, _) => None,
            (_, J::Number(n)) => {
                let x = finite_f32(n.as_f64()?)?;
                Value::float(x).convert(ty)
            }
            (_, J::Array(items)) if items.len() == ty.width() && ty != SocketType::Float => {
                let mut lanes = [0.0; 4];
                for (lane, item) in lanes.iter_mut().zip(items) {
                    *lane = finite_f32(item.as_f64()?)?;
                }
                Some(Value { ty, lanes })
            }
            _ => None,
        }
    }

    /// Infers the type of a JSON literal: a number is a float, an array of 2–4 numbers
    /// a vector, a bool a bool.
    pub fn infer_json(json: &serde_json::Value) -> Option<Value> {
        use serde_json::Value as J;
        let ty = match json {
            J::Bool(_) => SocketType::Bool,
            J::Number(_) => SocketType::Float,
            J::Array(a) => match a.len() {
                2 => SocketType::Vec2,
                3 => SocketType::Vec3,
                4 => SocketType::Vec4,
                _ => return None,
            },
            _ => return None,
        };
        Value::from_json(ty, json)
    }
}

/// The `f64` whose shortest decimal is the shortest decimal that reads back to `x` as an
/// `f32` (0.1f32 → 0.1, not 0.10000000149011612), so serde_json prints it that way.
pub fn shortest_f64(x: f32) -> f64 {
    format!("{x:?}").parse().unwrap_or(x as f64)
}

/// Serialises an `f32` as the shortest decimal that reads back to the same `f32`.
pub fn json_f32(x: f32) -> serde_json::Value {
    if !x.is_finite() {
        return serde_json::Value::Null;
    }
    serde_json::Number::from_f64(shortest_f64(x))
        .map(serde_json::Value::Number)
        .unwrap_or(serde_json::Value::Null)
}

fn finite_f32(x: f64) -> Option<f32> {
    let y = x as f32;
    y.is_finite().then_some(y)
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.ty {
            SocketType::Float => write!(f, "{:?}", self.lanes[0]),
            SocketType::Int => write!(f, "{}", self.as_i32()),
            SocketType::Bool => write!(f, "{}", self.as_bool()),
            _ => {
                f.write_str("[")?;
                for (i, x) in self.lanes().iter().enumerate() {
                    if i > 0 {
                        f.write_str(",")?;
                    }
                    write!(f, "{x:?}")?;
                }
                f.write_str("]")
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn json_numbers_broadcast_to_vectors() {
        let v = Value::from_json(SocketType::Vec3, &json!(0.5)).unwrap();
        assert_eq!(v, Value::vec3([0.5, 0.5, 0.5]));
    }

    #[test]
    fn json_arrays_need_the_right_width() {
        assert!(Value::from_json(SocketType::Vec3, &json!([1.0, 2.0])).is_none());
        assert!(Value::from_json(SocketType::Float, &json!([1.0])).is_none());
        assert!(Value::from_json(SocketType::Int, &json!(1.5)).is_none());
    }

    #[test]
    fn f32_json_is_shortest_round_trip() {
        assert_eq!(json_f32(0.1).to_string(), "0.1");
        assert_eq!(json_f32(1.0).to_string(), "1.0");
        assert_eq!(json_f32(1.0e-7).to_string(), "1e-7");
    }
}
