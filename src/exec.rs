//! The batched CPU executor: runs a [`Plan`] over structure-of-arrays tiles of [`TILE`]
//! samples, one kernel call per step per tile, tiles spread over threads with rayon.

use crate::node::Attribute;
use crate::plan::{EvalError, KernelRef, Operand, ParamValues, Plan, RegFill, TILE};
use crate::texture::{Filter, TextureSet, Wrap};
use crate::types::SocketType;
use crate::value::Value;
use glam::Vec2;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Per-sample inputs of one evaluation: attribute columns in planar layout (component `c`
/// of sample `i` at `c * len + i`) and the batch's time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SampleBatch {
    len: usize,
    time: f32,
    columns: BTreeMap<Attribute, Vec<f32>>,
    textures: Option<Arc<TextureSet>>,
}

impl SampleBatch {
    /// A batch of `len` samples; attributes not set take [`Attribute::default_value`].
    pub fn new(len: usize) -> SampleBatch {
        SampleBatch {
            len,
            time: 0.0,
            columns: BTreeMap::new(),
            textures: None,
        }
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.len
    }
    /// Whether the batch is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The batch's time in seconds.
    pub fn time(&self) -> f32 {
        self.time
    }
    /// Sets the time.
    pub fn set_time(&mut self, t: f32) {
        self.time = t;
    }
    /// Sets an attribute from planar data (`width × len` floats).
    pub fn set_planar(&mut self, attr: Attribute, data: Vec<f32>) -> Result<(), EvalError> {
        let expected = attr.ty().width() * self.len;
        if data.len() != expected || attr.is_uniform() {
            return Err(EvalError::AttributeLength {
                attribute: attr.name(),
                expected,
                found: data.len(),
            });
        }
        self.columns.insert(attr, data);
        Ok(())
    }
    /// Sets an attribute from one value per sample (interleaved), converting to planar.
    pub fn set_values(&mut self, attr: Attribute, values: &[[f32; 3]]) -> Result<(), EvalError> {
        let w = attr.ty().width();
        if values.len() != self.len {
            return Err(EvalError::AttributeLength {
                attribute: attr.name(),
                expected: self.len * w,
                found: values.len() * w,
            });
        }
        let mut data = vec![0.0; w * self.len];
        for (i, v) in values.iter().enumerate() {
            for c in 0..w {
                data[c * self.len + i] = v[c];
            }
        }
        self.set_planar(attr, data)
    }
    /// Sets an attribute to one value for every sample.
    pub fn fill(&mut self, attr: Attribute, value: Value) -> Result<(), EvalError> {
        if attr.is_uniform() {
            self.time = value.as_f32();
            return Ok(());
        }
        let w = attr.ty().width();
        let v = value.convert(attr.ty()).ok_or(EvalError::AttributeLength {
            attribute: attr.name(),
            expected: w,
            found: value.ty().width(),
        })?;
        let mut data = vec![0.0; w * self.len];
        for c in 0..w {
            data[c * self.len..(c + 1) * self.len].fill(v.lanes()[c]);
        }
        self.set_planar(attr, data)
    }
    /// Binds the textures that texture nodes sample, by key (see [`Plan::textures`]).
    pub fn set_textures(&mut self, textures: Arc<TextureSet>) {
        self.textures = Some(textures);
    }
    /// The bound textures.
    pub fn textures(&self) -> Option<&TextureSet> {
        self.textures.as_deref()
    }
    /// The planar column of an attribute, if set.
    pub fn column(&self, attr: Attribute) -> Option<&[f32]> {
        self.columns.get(&attr).map(Vec::as_slice)
    }
}

/// The results of one evaluation: one planar column per requested output.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputBatch {
    len: usize,
    names: Vec<String>,
    types: Vec<SocketType>,
    data: Vec<Vec<f32>>,
}

impl OutputBatch {
    /// Builds a batch from planar columns (used by backends).
    pub fn from_columns(
        len: usize,
        names: Vec<String>,
        types: Vec<SocketType>,
        data: Vec<Vec<f32>>,
    ) -> OutputBatch {
        OutputBatch {
            len,
            names,
            types,
            data,
        }
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.len
    }
    /// Whether the batch is empty.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// Output names, in request order.
    pub fn names(&self) -> &[String] {
        &self.names
    }
    /// Type of output `k`.
    pub fn ty(&self, k: usize) -> SocketType {
        self.types[k]
    }
    /// Planar data of output `k` (component `c` of sample `i` at `c * len + i`).
    pub fn planar(&self, k: usize) -> &[f32] {
        &self.data[k]
    }
    /// Index of the output called `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Output `k` at sample `i`.
    pub fn value(&self, k: usize, i: usize) -> Value {
        let ty = self.types[k];
        let mut lanes = [0.0; 4];
        for (c, lane) in lanes.iter_mut().enumerate().take(ty.width()) {
            *lane = self.data[k][c * self.len + i];
        }
        Value::from_lanes(ty, &lanes)
    }
}

/// Something that evaluates a compiled graph over a batch: the CPU executor, or the GPU.
pub trait Evaluator {
    /// Evaluates every requested output for every sample of `batch`.
    fn evaluate(&self, batch: &SampleBatch, params: &ParamValues)
    -> Result<OutputBatch, EvalError>;
}

impl Evaluator for Plan {
    fn evaluate(
        &self,
        batch: &SampleBatch,
        params: &ParamValues,
    ) -> Result<OutputBatch, EvalError> {
        self.execute(batch, params)
    }
}

/// What every tile of one evaluation shares.
#[derive(Clone, Copy)]
struct Run<'a> {
    batch: &'a SampleBatch,
    /// Attribute registers to fill from the batch's columns.
    attrs: &'a [(usize, Attribute)],
    /// The uniform program's results.
    uniforms: &'a [Value],
    /// Index in the batch's texture set of each texture slot.
    tex: &'a [u32],
}

/// A worker's registers: one buffer of `width × TILE` floats per register.
struct Scratch {
    regs: Vec<Box<[f32]>>,
    outs: Vec<Box<[f32]>>,
}

impl Plan {
    /// Runs the uniform program: parameters, time and hoisted nodes, once per evaluation.
    fn uniforms(&self, batch: &SampleBatch, params: &ParamValues) -> Vec<Value> {
        let mut slots = self.uniform_init.clone();
        for (p, v) in self.parameters.iter().zip(params.values()) {
            if let Some(s) = p.slot {
                slots[s as usize] = *v;
            }
        }
        if let Some(s) = self.time_slot {
            slots[s as usize] = Value::float(batch.time());
        }
        crate::plan::run_uniform_steps(&self.uniform_steps, &mut slots);
        slots
    }

    /// A worker's scratch, with constant, uniform and absent-attribute registers filled.
    fn scratch(&self, uniforms: &[Value], batch: &SampleBatch) -> Scratch {
        let regs = self
            .registers
            .iter()
            .map(|r| {
                let mut buf = vec![0.0f32; r.width * TILE].into_boxed_slice();
                let fill = match r.fill {
                    RegFill::Const(v) => Some(v),
                    RegFill::Uniform(s) => Some(uniforms[s as usize]),
                    RegFill::Attribute(a) if batch.column(a).is_none() => Some(a.default_value()),
                    _ => None,
                };
                if let Some(v) = fill {
                    for c in 0..r.width {
                        buf[c * TILE..(c + 1) * TILE].fill(v.raw()[c]);
                    }
                }
                buf
            })
            .collect();
        Scratch {
            regs,
            outs: Vec::with_capacity(8),
        }
    }

    /// The index in the batch's texture set of each texture the plan samples.
    pub(crate) fn bind_textures(&self, batch: &SampleBatch) -> Result<Vec<u32>, EvalError> {
        self.textures
            .iter()
            .map(|key| {
                batch
                    .textures()
                    .and_then(|set| set.index_of(key))
                    .ok_or_else(|| EvalError::MissingTexture { name: key.clone() })
            })
            .collect()
    }

    /// Evaluates the plan over `batch` on the current rayon pool.
    pub fn execute(
        &self,
        batch: &SampleBatch,
        params: &ParamValues,
    ) -> Result<OutputBatch, EvalError> {
        if params.values().len() != self.parameters.len() {
            return Err(EvalError::UnknownParameter {
                name: "(parameter set of another plan)".into(),
                suggestion: None,
            });
        }
        let len = batch.len();
        let uniforms = self.uniforms(batch, params);
        let tex = self.bind_textures(batch)?;
        let mut data: Vec<Vec<f32>> = self
            .outputs
            .iter()
            .map(|o| vec![0.0; o.ty.width() * len])
            .collect();

        // Per tile, the slices of every output component it writes.
        let cols_per_tile: usize = self.outputs.iter().map(|o| o.ty.width()).sum();
        let tiles = len.div_ceil(TILE);
        let mut views: Vec<Option<&mut [f32]>> = (0..tiles * cols_per_tile).map(|_| None).collect();
        let mut col = 0;
        for (o, d) in self.outputs.iter().zip(data.iter_mut()) {
            for comp in d.chunks_mut(len.max(1)).take(o.ty.width()) {
                for (t, chunk) in comp.chunks_mut(TILE).enumerate() {
                    views[t * cols_per_tile + col] = Some(chunk);
                }
                col += 1;
            }
        }
        let attrs: Vec<(usize, Attribute)> = self
            .registers
            .iter()
            .enumerate()
            .filter_map(|(r, reg)| match reg.fill {
                RegFill::Attribute(a) if batch.column(a).is_some() => Some((r, a)),
                _ => None,
            })
            .collect();

        let run = Run {
            batch,
            attrs: &attrs,
            uniforms: &uniforms,
            tex: &tex,
        };
        if cols_per_tile > 0 {
            views
                .par_chunks_mut(cols_per_tile)
                .enumerate()
                .for_each_init(
                    || self.scratch(&uniforms, batch),
                    |scratch, (t, out)| self.run_tile(scratch, &run, t, out),
                );
        }
        Ok(OutputBatch {
            len,
            names: self.outputs.iter().map(|o| o.name.clone()).collect(),
            types: self.outputs.iter().map(|o| o.ty).collect(),
            data,
        })
    }

    fn run_tile(&self, scratch: &mut Scratch, run: &Run, t: usize, out: &mut [Option<&mut [f32]>]) {
        let Run {
            batch,
            attrs,
            uniforms,
            tex,
        } = *run;
        let len = batch.len();
        let start = t * TILE;
        let n = TILE.min(len - start);
        for &(r, a) in attrs {
            let src = batch.column(a).unwrap_or_default();
            let buf = &mut scratch.regs[r];
            for c in 0..a.ty().width() {
                buf[c * TILE..c * TILE + n]
                    .copy_from_slice(&src[c * len + start..c * len + start + n]);
            }
        }
        for step in &self.steps {
            scratch.outs.clear();
            for &r in &step.outputs {
                scratch
                    .outs
                    .push(std::mem::take(&mut scratch.regs[r as usize]));
            }
            let mut ins: [&[f32]; crate::kernel::MAX_INPUTS] = [&[]; crate::kernel::MAX_INPUTS];
            for (slot, &r) in ins.iter_mut().zip(&step.inputs) {
                *slot = &scratch.regs[r as usize];
            }
            let mut outs: [&mut [f32]; crate::kernel::MAX_OUTPUTS] = Default::default();
            for (slot, buf) in outs.iter_mut().zip(scratch.outs.iter_mut()) {
                *slot = buf;
            }
            match (step.kernel.kernel(), &step.kernel, batch.textures()) {
                (Some(k), ..) => k.run(
                    &ins[..step.inputs.len()],
                    &mut outs[..step.outputs.len()],
                    TILE,
                    n,
                ),
                (None, KernelRef::Texture(slot, None), Some(set)) => sample_tile(
                    set,
                    tex[*slot],
                    &ins[..step.inputs.len()],
                    &mut outs[..step.outputs.len()],
                    n,
                ),
                (None, KernelRef::Texture(slot, Some(k)), Some(set)) => {
                    let t = tex[*slot];
                    let sample = |uv: Vec2, lod: f32, wrap: Wrap, filter: Filter| {
                        set.sample(t, uv, lod, wrap, filter)
                    };
                    k(
                        &sample,
                        &ins[..step.inputs.len()],
                        &mut outs[..step.outputs.len()],
                        n,
                    )
                }
                _ => {}
            }
            for (&r, buf) in step.outputs.iter().zip(scratch.outs.drain(..)) {
                scratch.regs[r as usize] = buf;
            }
        }
        let mut col = 0;
        for o in &self.outputs {
            for c in 0..o.ty.width() {
                let dst = out[col].as_deref_mut().unwrap_or_default();
                match o.operand {
                    Operand::Reg(r) => {
                        dst.copy_from_slice(&scratch.regs[r as usize][c * TILE..c * TILE + n])
                    }
                    Operand::Const(v) => dst.fill(v.raw()[c]),
                    Operand::Uniform(s) => dst.fill(uniforms[s as usize].raw()[c]),
                }
                col += 1;
            }
        }
    }
}

/// Samples texture `tex` for `n` samples of a tile: inputs uv (vec2), lod, wrap, filter;
/// outputs colour (rgb) and alpha.
fn sample_tile(set: &TextureSet, tex: u32, ins: &[&[f32]], outs: &mut [&mut [f32]], n: usize) {
    let (uv, lod, wrap, filter) = (ins[0], ins[1], ins[2], ins[3]);
    for i in 0..n {
        let c = set.sample(
            tex,
            Vec2::new(uv[i], uv[TILE + i]),
            lod[i],
            Wrap::from_index(wrap[i] as u32),
            Filter::from_index(filter[i] as u32),
        );
        outs[0][i] = c.x;
        outs[0][TILE + i] = c.y;
        outs[0][2 * TILE + i] = c.z;
        outs[1][i] = c.w;
    }
}
