//! The parameter block `MgParams` with a typed writer: [`ParamBlock::set`] checks the name
//! and type and [`ParamBlock::bytes`] writes every member at the offset naga computed.

use super::MaterialError;
use crate::plan::ParamValues;
use crate::value::Value;
use crate::wgsl::{UniformLayout, UniformSource};

/// A value [`ParamBlock::set`] accepts: `f32`, `[f32; 2]`, `[f32; 3]`, `[f32; 4]`, `i32`,
/// `bool` or a [`Value`].
pub trait IntoParam {
    /// The value, typed.
    fn into_value(self) -> Value;
}

impl IntoParam for Value {
    fn into_value(self) -> Value {
        self
    }
}
impl IntoParam for f32 {
    fn into_value(self) -> Value {
        Value::float(self)
    }
}
impl IntoParam for [f32; 2] {
    fn into_value(self) -> Value {
        Value::vec2(self)
    }
}
impl IntoParam for [f32; 3] {
    fn into_value(self) -> Value {
        Value::vec3(self)
    }
}
impl IntoParam for [f32; 4] {
    fn into_value(self) -> Value {
        Value::vec4(self)
    }
}
impl IntoParam for i32 {
    fn into_value(self) -> Value {
        Value::int(self)
    }
}
impl IntoParam for bool {
    fn into_value(self) -> Value {
        Value::boolean(self)
    }
}

/// The contents of the parameter uniform (`mg_params`, group 0 binding 0): the graph's
/// exposed parameters, its fixed parameter nodes and the time, at naga's offsets.
#[derive(Clone, Debug)]
pub struct ParamBlock {
    layout: UniformLayout,
    values: ParamValues,
    time: f32,
}

impl ParamBlock {
    pub(super) fn new(layout: UniformLayout, values: ParamValues) -> ParamBlock {
        ParamBlock {
            layout,
            values,
            time: 0.0,
        }
    }

    /// Sets parameter `name` (a float is broadcast to a vector parameter; an int or bool
    /// converts as a link would). Errors name the parameter: unknown (with the nearest name),
    /// of another type (with the type expected), or outside the hard range of an input it
    /// feeds. The value is unchanged on an error.
    pub fn set(&mut self, name: &str, value: impl IntoParam) -> Result<(), MaterialError> {
        self.values
            .set(name, value.into_value())
            .map_err(MaterialError::Parameter)
    }

    /// Replaces every parameter value by `values`'s (e.g. the values a CPU plan of the same
    /// graph executes with, so both evaluate alike); members `values` lacks keep their
    /// defaults. Unchecked: `values` comes from a plan, which checked it.
    pub fn set_values(&mut self, values: &ParamValues) {
        self.values = values.clone();
    }

    /// Sets the time in seconds (the `time` member, when the graph reads time).
    pub fn set_time(&mut self, seconds: f32) {
        self.time = seconds;
    }

    /// The value of parameter `name`.
    pub fn get(&self, name: &str) -> Option<Value> {
        self.values.get(name)
    }

    /// The parameter values (what [`crate::Plan::execute`] takes: CPU and GPU stay in step).
    pub fn values(&self) -> &ParamValues {
        &self.values
    }

    /// The time in seconds.
    pub fn time(&self) -> f32 {
        self.time
    }

    /// The block's layout, from naga: size and each member's offset and type.
    pub fn layout(&self) -> &UniformLayout {
        &self.layout
    }

    /// Whether the module has a parameter block at all (no member: no binding 0).
    pub fn is_empty(&self) -> bool {
        self.layout.fields.is_empty()
    }

    /// The bytes to write into the uniform buffer: little-endian, each member at its offset
    /// (bools as `u32` 0 or 1), padded with zeros to a multiple of 16 and at least 16 bytes.
    pub fn bytes(&self) -> Vec<u8> {
        let mut b = self.layout.pack(&self.values, self.time);
        b.resize((b.len().next_multiple_of(16)).max(16), 0);
        b
    }

    /// The byte offset of parameter `name`'s member, if it is in the block.
    pub fn offset_of(&self, name: &str) -> Option<u32> {
        self.layout
            .fields
            .iter()
            .find(|f| matches!(&f.source, UniformSource::Parameter(p) if p == name))
            .map(|f| f.offset)
    }
}
