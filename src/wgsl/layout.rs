//! The layout of the parameter uniform block, read from naga's struct member offsets (which
//! include WGSL's vec3 padding), and packing parameter values into it.

use super::emit::UniformSpec;
use crate::plan::ParamValues;
use crate::types::SocketType;
use crate::value::Value;

/// Where a member of `MgParams` gets its value.
#[derive(Clone, Debug, PartialEq)]
pub enum UniformSource {
    /// An exposed parameter, set by name through `ParamValues`.
    Parameter(String),
    /// A `parameter` node the graph does not list: its value from the file.
    Fixed,
    /// The batch's time.
    Time,
    /// A node's constant table (`array<vec4<f32>, N>`, see [`crate::node::WgslTable`]):
    /// its rows, written as they are.
    Table(&'static [[f32; 4]]),
}

/// The WGSL type of a `MgParams` member from `source` of socket type `ty`.
pub(super) fn member_type(source: &UniformSource, ty: SocketType) -> String {
    match (source, ty) {
        (UniformSource::Table(rows), _) => format!("array<vec4<f32>, {}>", rows.len()),
        (_, SocketType::Bool) => "u32".into(),
        (_, t) => super::wgsl_type(t).into(),
    }
}

/// One member of `MgParams`.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformField {
    /// WGSL member name.
    pub field: String,
    /// Where its value comes from.
    pub source: UniformSource,
    /// Its type (bools are stored as `u32`; for a table, its row type `Vec4`).
    pub ty: SocketType,
    /// Byte offset from naga.
    pub offset: u32,
    /// Value used when the caller sets none.
    pub default: Value,
}

/// The layout of `MgParams`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UniformLayout {
    /// Size in bytes, as naga computed it (a multiple of the struct's alignment).
    pub size: u32,
    /// Members in declaration order.
    pub fields: Vec<UniformField>,
}

impl UniformField {
    /// Its WGSL type (bools are `u32`; tables `array<vec4<f32>, N>`).
    pub fn wgsl_type(&self) -> String {
        member_type(&self.source, self.ty)
    }
}

impl UniformLayout {
    /// Reads the layout of `MgParams` from a validated module.
    pub(super) fn read(module: &naga::Module, specs: &[UniformSpec]) -> UniformLayout {
        let Some((members, span)) =
            module
                .types
                .iter()
                .find_map(|(_, t)| match (&t.name, &t.inner) {
                    (Some(name), naga::TypeInner::Struct { members, span })
                        if name == "MgParams" =>
                    {
                        Some((members, *span))
                    }
                    _ => None,
                })
        else {
            return UniformLayout::default();
        };
        let fields = members
            .iter()
            .zip(specs)
            .map(|(m, s)| UniformField {
                field: s.field.clone(),
                source: s.source.clone(),
                ty: s.ty,
                offset: m.offset,
                default: s.default,
            })
            .collect();
        UniformLayout { size: span, fields }
    }

    /// The bytes of the block for these parameter values and time.
    pub fn pack(&self, params: &ParamValues, time: f32) -> Vec<u8> {
        let mut bytes = vec![0u8; self.size as usize];
        for f in &self.fields {
            let at = f.offset as usize;
            let v = match &f.source {
                UniformSource::Parameter(name) => params.get(name).unwrap_or(f.default),
                UniformSource::Fixed => f.default,
                UniformSource::Time => Value::float(time),
                UniformSource::Table(rows) => {
                    for (k, x) in rows.iter().flatten().enumerate() {
                        bytes[at + 4 * k..at + 4 * k + 4].copy_from_slice(&x.to_le_bytes());
                    }
                    continue;
                }
            };
            match f.ty {
                SocketType::Int => bytes[at..at + 4].copy_from_slice(&v.as_i32().to_le_bytes()),
                SocketType::Bool => {
                    bytes[at..at + 4].copy_from_slice(&(v.as_bool() as u32).to_le_bytes())
                }
                _ => {
                    for (c, x) in v.lanes().iter().enumerate() {
                        bytes[at + 4 * c..at + 4 * c + 4].copy_from_slice(&x.to_le_bytes());
                    }
                }
            }
        }
        bytes
    }
}
