//! The bridge from a node's one-sample compute function to a whole-tile kernel.
//!
//! A node's CPU compute is plain Rust over one sample (`fn(f32, Vec3) -> (f32, f32)`).
//! [`kernel`] wraps it into a [`TileKernel`] whose `run` loops over a structure-of-arrays
//! tile; the compute function is monomorphised into that loop, so the executor pays one
//! dynamic call per node per tile and the per-sample work is inlined (and often vectorised).

use crate::types::SocketType;
use glam::{Vec2, Vec3, Vec4};
use std::marker::PhantomData;

/// The shape of a [`Lane`] value, used to check a compute function against its ports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// `f32`.
    Scalar,
    /// `i32`, stored as an exact float.
    Int,
    /// `bool`, stored as 0.0 / 1.0.
    Bool,
    /// `Vec2`.
    Vec2,
    /// `Vec3` (vec3 and color ports).
    Vec3,
    /// `Vec4`.
    Vec4,
}

impl Shape {
    /// The shape that carries a socket type.
    pub const fn of(ty: SocketType) -> Shape {
        match ty {
            SocketType::Float => Shape::Scalar,
            SocketType::Int => Shape::Int,
            SocketType::Bool => Shape::Bool,
            SocketType::Vec2 => Shape::Vec2,
            SocketType::Vec3 | SocketType::Color => Shape::Vec3,
            SocketType::Vec4 => Shape::Vec4,
        }
    }
}

/// A per-sample value type that lives in `WIDTH` planar `f32` columns of a tile.
pub trait Lane: Copy + Send + Sync + 'static {
    /// Shape checked against the declared port type.
    const SHAPE: Shape;
    /// Number of columns.
    const WIDTH: usize;
    /// Reads sample `i` from columns `c` (each at least `i + 1` long).
    fn read(c: &[&[f32]; 4], i: usize) -> Self;
    /// Writes sample `i` into columns `c`.
    fn write(self, c: &mut [&mut [f32]; 4], i: usize);
}

impl Lane for f32 {
    const SHAPE: Shape = Shape::Scalar;
    const WIDTH: usize = 1;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        c[0][i]
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = self;
    }
}

impl Lane for i32 {
    const SHAPE: Shape = Shape::Int;
    const WIDTH: usize = 1;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        c[0][i] as i32
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = self as f32;
    }
}

impl Lane for bool {
    const SHAPE: Shape = Shape::Bool;
    const WIDTH: usize = 1;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        c[0][i] != 0.0
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = if self { 1.0 } else { 0.0 };
    }
}

impl Lane for Vec2 {
    const SHAPE: Shape = Shape::Vec2;
    const WIDTH: usize = 2;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        Vec2::new(c[0][i], c[1][i])
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = self.x;
        c[1][i] = self.y;
    }
}

impl Lane for Vec3 {
    const SHAPE: Shape = Shape::Vec3;
    const WIDTH: usize = 3;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        Vec3::new(c[0][i], c[1][i], c[2][i])
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = self.x;
        c[1][i] = self.y;
        c[2][i] = self.z;
    }
}

impl Lane for Vec4 {
    const SHAPE: Shape = Shape::Vec4;
    const WIDTH: usize = 4;
    #[inline(always)]
    fn read(c: &[&[f32]; 4], i: usize) -> Self {
        Vec4::new(c[0][i], c[1][i], c[2][i], c[3][i])
    }
    #[inline(always)]
    fn write(self, c: &mut [&mut [f32]; 4], i: usize) {
        c[0][i] = self.x;
        c[1][i] = self.y;
        c[2][i] = self.z;
        c[3][i] = self.w;
    }
}

/// Splits a register buffer into up to four planar columns of `len` samples, `stride` apart.
#[inline(always)]
fn columns(buf: &[f32], width: usize, stride: usize, len: usize) -> [&[f32]; 4] {
    let mut c: [&[f32]; 4] = [&[]; 4];
    for (k, col) in c.iter_mut().enumerate().take(width) {
        *col = &buf[k * stride..k * stride + len];
    }
    c
}

/// Mutable counterpart of [`columns`].
#[inline(always)]
fn columns_mut(buf: &mut [f32], width: usize, stride: usize, len: usize) -> [&mut [f32]; 4] {
    let mut out: [&mut [f32]; 4] = [&mut [], &mut [], &mut [], &mut []];
    let mut rest = buf;
    for (k, col) in out.iter_mut().enumerate().take(width) {
        let (head, tail) =
            std::mem::take(&mut rest).split_at_mut(if k + 1 < width { stride } else { len });
        *col = &mut head[..len];
        rest = tail;
    }
    out
}

/// The most outputs a node may have.
pub const MAX_OUTPUTS: usize = 8;

/// The most inputs a node's kernel takes (`rgb_curves` has 70: its points are sockets).
pub const MAX_INPUTS: usize = 80;

/// The outputs of a compute function: one [`Lane`] or a tuple of them.
pub trait Outputs: Copy + Send + Sync + 'static {
    /// Shapes of the outputs in order.
    fn shapes() -> Vec<Shape>;
    /// Number of outputs.
    const COUNT: usize;
    /// Column width of each output.
    const WIDTHS: &'static [usize];
    /// Writes sample `i` into the output columns.
    fn write(self, cols: &mut [[&mut [f32]; 4]], i: usize);
}

impl<L: Lane> Outputs for L {
    fn shapes() -> Vec<Shape> {
        vec![L::SHAPE]
    }
    const COUNT: usize = 1;
    const WIDTHS: &'static [usize] = &[L::WIDTH];
    #[inline(always)]
    fn write(self, cols: &mut [[&mut [f32]; 4]], i: usize) {
        Lane::write(self, &mut cols[0], i);
    }
}

macro_rules! impl_outputs_tuple {
    ($n:expr; $($t:ident $idx:tt),+) => {
        impl<$($t: Lane),+> Outputs for ($($t,)+) {
            fn shapes() -> Vec<Shape> {
                vec![$($t::SHAPE),+]
            }
            const COUNT: usize = $n;
            const WIDTHS: &'static [usize] = &[$($t::WIDTH),+];
            #[inline(always)]
            fn write(self, cols: &mut [[&mut [f32]; 4]], i: usize) {
                $( Lane::write(self.$idx, &mut cols[$idx], i); )+
            }
        }
    };
}
impl_outputs_tuple!(1; A 0);
impl_outputs_tuple!(2; A 0, B 1);
impl_outputs_tuple!(3; A 0, B 1, C 2);
impl_outputs_tuple!(4; A 0, B 1, C 2, D 3);
impl_outputs_tuple!(5; A 0, B 1, C 2, D 3, E 4);
impl_outputs_tuple!(6; A 0, B 1, C 2, D 3, E 4, F 5);
impl_outputs_tuple!(7; A 0, B 1, C 2, D 3, E 4, F 5, G 6);
impl_outputs_tuple!(8; A 0, B 1, C 2, D 3, E 4, F 5, G 6, H 7);
impl_outputs_tuple!(9; A 0, B 1, C 2, D 3, E 4, F 5, G 6, H 7, I 8);
impl_outputs_tuple!(10; A 0, B 1, C 2, D 3, E 4, F 5, G 6, H 7, I 8, J 9);

/// A whole-tile kernel: what the executor calls once per node per tile.
pub trait TileKernel: Send + Sync {
    /// Shapes of the inputs, in port order.
    fn input_shapes(&self) -> Vec<Shape>;
    /// Shapes of the outputs, in port order.
    fn output_shapes(&self) -> Vec<Shape>;
    /// Runs `len` samples. `inputs[k]` holds input `k`'s columns `stride` apart; each
    /// `outputs[k]` likewise. Buffers are at least `(width - 1) * stride + len` long.
    fn run(&self, inputs: &[&[f32]], outputs: &mut [&mut [f32]], stride: usize, len: usize);
}

/// A one-sample compute function with arguments `Args`, adaptable to a [`TileKernel`].
pub trait SampleFn<Args>: Copy + Send + Sync + 'static {
    /// Shapes of the arguments in order.
    fn input_shapes() -> Vec<Shape>;
    /// Shapes of the results in order.
    fn output_shapes() -> Vec<Shape>;
    /// Runs the tile loop.
    fn run_tile(&self, inputs: &[&[f32]], outputs: &mut [&mut [f32]], stride: usize, len: usize);
}

/// Wraps a compute function into a boxed [`TileKernel`].
pub fn kernel<F, Args>(f: F) -> Box<dyn TileKernel>
where
    F: SampleFn<Args>,
    Args: 'static,
{
    Box::new(FnKernel {
        f,
        _args: PhantomData::<fn() -> Args>,
    })
}

struct FnKernel<F, Args> {
    f: F,
    _args: PhantomData<fn() -> Args>,
}

impl<F: SampleFn<Args>, Args: 'static> TileKernel for FnKernel<F, Args> {
    fn input_shapes(&self) -> Vec<Shape> {
        F::input_shapes()
    }
    fn output_shapes(&self) -> Vec<Shape> {
        F::output_shapes()
    }
    fn run(&self, inputs: &[&[f32]], outputs: &mut [&mut [f32]], stride: usize, len: usize) {
        self.f.run_tile(inputs, outputs, stride, len)
    }
}

/// Splits every output buffer into its planar columns.
#[inline(always)]
fn output_columns<'a, R: Outputs>(
    outputs: &'a mut [&mut [f32]],
    stride: usize,
    len: usize,
) -> [[&'a mut [f32]; 4]; MAX_OUTPUTS] {
    let mut cols: [[&'a mut [f32]; 4]; MAX_OUTPUTS] = Default::default();
    for ((slot, buf), &width) in cols.iter_mut().zip(outputs.iter_mut()).zip(R::WIDTHS) {
        *slot = columns_mut(buf, width, stride, len);
    }
    cols
}

macro_rules! impl_sample_fn {
    ($($a:ident $idx:tt),*) => {
        impl<Func, R, $($a),*> SampleFn<($($a,)*)> for Func
        where
            Func: Fn($($a),*) -> R + Copy + Send + Sync + 'static,
            R: Outputs,
            $($a: Lane,)*
        {
            fn input_shapes() -> Vec<Shape> {
                vec![$($a::SHAPE),*]
            }
            fn output_shapes() -> Vec<Shape> {
                R::shapes()
            }
            #[inline(never)]
            #[allow(unused_variables, non_snake_case)]
            fn run_tile(&self, inputs: &[&[f32]], outputs: &mut [&mut [f32]], stride: usize, len: usize) {
                $( let $a = columns(inputs[$idx], $a::WIDTH, stride, len); )*
                let mut out = output_columns::<R>(outputs, stride, len);
                for i in 0..len {
                    let r = (self)($($a::read(&$a, i)),*);
                    r.write(&mut out, i);
                }
            }
        }
    };
}

impl_sample_fn!();
impl_sample_fn!(A0 0);
impl_sample_fn!(A0 0, A1 1);
impl_sample_fn!(A0 0, A1 1, A2 2);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10, A11 11);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10, A11 11, A12 12);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10, A11 11, A12 12, A13 13);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10, A11 11, A12 12, A13 13, A14 14);
impl_sample_fn!(A0 0, A1 1, A2 2, A3 3, A4 4, A5 5, A6 6, A7 7, A8 8, A9 9, A10 10, A11 11, A12 12, A13 13, A14 14, A15 15);

#[cfg(test)]
mod tests {
    use super::*;

    fn fused(a: f32, b: Vec3) -> (f32, Vec3) {
        (a * 2.0, b * a)
    }

    #[test]
    fn tile_kernel_runs_the_sample_function_per_lane() {
        let k = kernel(fused);
        assert_eq!(k.input_shapes(), vec![Shape::Scalar, Shape::Vec3]);
        assert_eq!(k.output_shapes(), vec![Shape::Scalar, Shape::Vec3]);
        let stride = 4;
        let a = [1.0, 2.0, 3.0, 0.0];
        let b = [1.0, 1.0, 1.0, 0.0, 2.0, 2.0, 2.0, 0.0, 3.0, 3.0, 3.0, 0.0];
        let mut o0 = [0.0f32; 4];
        let mut o1 = [0.0f32; 12];
        let mut outs: [&mut [f32]; 2] = [&mut o0, &mut o1];
        k.run(&[&a, &b], &mut outs, stride, 3);
        assert_eq!(o0, [2.0, 4.0, 6.0, 0.0]);
        assert_eq!(&o1[..3], &[1.0, 2.0, 3.0]);
        assert_eq!(&o1[4..7], &[2.0, 4.0, 6.0]);
        assert_eq!(&o1[8..11], &[3.0, 6.0, 9.0]);
    }
}
