//! CPU kernels of nodes with more inputs than a compute function takes (sixteen arguments,
//! [`crate::kernel`]): a ramp's or a curve's stops are sockets of their own, 35 to 70 of
//! them. A [`WideFn`] computes one sample from every input lane gathered into one flat
//! array, in port order, and writes every output lane into another; [`Wide`] adapts it to
//! the [`SampleFn`] that [`crate::node::NodeType::compute`] takes.

use crate::kernel::{SampleFn, Shape};
use std::marker::PhantomData;

/// The most input lanes (or output lanes) a [`WideFn`] may have.
pub const MAX_LANES: usize = 160;

/// The lanes a value of shape `s` takes.
pub const fn lanes(s: Shape) -> usize {
    match s {
        Shape::Scalar | Shape::Int | Shape::Bool => 1,
        Shape::Vec2 => 2,
        Shape::Vec3 => 3,
        Shape::Vec4 => 4,
    }
}

/// A one-sample compute over flat lanes.
pub trait WideFn: Copy + Send + Sync + 'static {
    /// The inputs' shapes, in port order.
    const INPUTS: &'static [Shape];
    /// The outputs' shapes, in port order.
    const OUTPUTS: &'static [Shape];
    /// Computes one sample: `ins` holds every input lane in port order (ints and bools as
    /// exact floats), `outs` receives every output lane in port order.
    fn sample(ins: &[f32], outs: &mut [f32]);
}

/// The argument marker of [`Wide`]'s [`SampleFn`] (no tuple: one flat array).
pub struct WideArgs;

/// A [`WideFn`] as a [`SampleFn`].
pub struct Wide<F>(PhantomData<F>);

impl<F> Wide<F> {
    /// The adapter of `F`.
    pub const fn new() -> Wide<F> {
        Wide(PhantomData)
    }
}

impl<F> Default for Wide<F> {
    fn default() -> Self {
        Wide::new()
    }
}

impl<F> Clone for Wide<F> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<F> Copy for Wide<F> {}

impl<F: WideFn> SampleFn<WideArgs> for Wide<F> {
    fn input_shapes() -> Vec<Shape> {
        F::INPUTS.to_vec()
    }
    fn output_shapes() -> Vec<Shape> {
        F::OUTPUTS.to_vec()
    }
    fn run_tile(&self, inputs: &[&[f32]], outputs: &mut [&mut [f32]], stride: usize, len: usize) {
        let mut ins = [0.0f32; MAX_LANES];
        let mut outs = [0.0f32; MAX_LANES];
        for i in 0..len {
            let mut at = 0;
            for (k, &s) in F::INPUTS.iter().enumerate() {
                for c in 0..lanes(s) {
                    ins[at] = inputs[k][c * stride + i];
                    at += 1;
                }
            }
            F::sample(&ins[..at], &mut outs);
            let mut at = 0;
            for (k, &s) in F::OUTPUTS.iter().enumerate() {
                for c in 0..lanes(s) {
                    outputs[k][c * stride + i] = outs[at];
                    at += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::kernel;

    /// 20 inputs (more than a compute function takes): the sum of the scalars, and the
    /// vec2's components swapped.
    #[derive(Clone, Copy)]
    struct Twenty;

    impl WideFn for Twenty {
        const INPUTS: &'static [Shape] = &[
            Shape::Vec2,
            Shape::Int,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
            Shape::Scalar,
        ];
        const OUTPUTS: &'static [Shape] = &[Shape::Scalar, Shape::Vec2];
        fn sample(ins: &[f32], outs: &mut [f32]) {
            assert_eq!(ins.len(), 21);
            outs[0] = ins[2..].iter().sum();
            outs[1] = ins[1];
            outs[2] = ins[0];
        }
    }

    #[test]
    fn a_wide_kernel_reads_planar_columns_and_writes_them() {
        let k = kernel(Wide::<Twenty>::new());
        assert_eq!(k.input_shapes().len(), 20);
        assert_eq!(k.output_shapes(), vec![Shape::Scalar, Shape::Vec2]);
        // Two samples, stride 3 (the third row is padding the kernel must not read).
        let v2 = [1.0, 2.0, -9.0, 10.0, 20.0, -9.0];
        let int = [7.0, 8.0, -9.0];
        let scalars: Vec<[f32; 3]> = (0..18).map(|j| [j as f32, 100.0, -9.0]).collect();
        let mut ins: Vec<&[f32]> = vec![&v2, &int];
        ins.extend(scalars.iter().map(|s| s.as_slice()));
        let mut o0 = [0.0f32; 3];
        let mut o1 = [0.0f32; 6];
        let mut outs: [&mut [f32]; 2] = [&mut o0, &mut o1];
        k.run(&ins, &mut outs, 3, 2);
        // Sample 0: 7 (the int) + 0 + 1 + … + 17 = 160; sample 1: 8 + 18·100.
        assert_eq!(o0, [160.0, 1808.0, 0.0]);
        // The vec2 (x, y) = (1, 10) and (2, 20), swapped.
        assert_eq!(o1, [10.0, 20.0, 0.0, 1.0, 2.0, 0.0]);
    }
}
