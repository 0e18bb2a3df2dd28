//! Ports as typed records: one `In` and one `Out` struct per unit and per
//! sub-block (an operator, a unit's block), generic over what a port
//! carries — a [`Sig`] in the generator, a `u64` word in a testbench,
//! `usize` for positions, `()` for the list of names. The record's one
//! [`Record::walk`] names its ports in order, so a module's ports, every
//! instance's connections ([`instance`]), its `ports.json` and every
//! testbench's packing come from the same lines and a port added to a
//! module cannot shift the others.

use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use std::fmt::Display;
use std::marker::PhantomData;
use std::sync::Arc;

/// The axes of a vector, in port order.
pub const AXES: [&str; 3] = ["x", "y", "z"];

/// A walk's visitor: given each port's name (formatted only where it is
/// needed, so packing a vector allocates nothing), type, and the record's
/// value when a record is read; returns the port's value. A type parameter,
/// not a trait object, so packing compiles to plain loads and stores.
pub trait Visit<T>: FnMut(&dyn Display, Ty, Option<T>) -> T {}

impl<T, F: FnMut(&dyn Display, Ty, Option<T>) -> T> Visit<T> for F {}

/// What a record's [`Record::walk`] visits its ports with, in port order.
///
/// Making a record (`from` is `None`): each port's value comes from the
/// visitor (an input it declares, a word it reads). Reading one (`from` is
/// the record): each field's value is handed to the visitor (an output to
/// declare, a word to write) and kept.
pub struct Walk<'a, T, R, V> {
    from: Option<&'a R>,
    visit: V,
    value: PhantomData<T>,
}

impl<T: Copy, R, V: Visit<T>> Walk<'_, T, R, V> {
    /// Port `name` of type `ty` (a `&str`, or `format_args!` for a
    /// numbered port): the record's `field`.
    pub fn one(&mut self, name: impl Display, ty: Ty, field: impl Fn(&R) -> T) -> T {
        let have = self.from.map(field);
        (self.visit)(&name, ty, have)
    }

    /// The vector ports `{group}_x`, `{group}_y`, `{group}_z` of type `ty`:
    /// the record's `field`.
    pub fn xyz(&mut self, group: impl Display, ty: Ty, field: impl Fn(&R) -> [T; 3]) -> [T; 3] {
        let have = self.from.map(field);
        let mut axis = |i: usize| {
            let name = format_args!("{group}_{}", AXES[i]);
            (self.visit)(&name, ty, have.map(|h| h[i]))
        };
        // not `[0, 1, 2].map(..)`: its closure is not inlined into a vector's packing
        [axis(0), axis(1), axis(2)]
    }
}

/// A record of a unit's input or output ports.
pub trait Record<T: Copy>: Sized {
    /// What decides which ports exist and their types.
    type Config;
    /// Visits every port of `cfg` in port order (see [`Walk`]) and returns
    /// the record of the values it gave or kept. A field without a port in
    /// `cfg` takes the value the unit gives it (a ray's upper bounds are its
    /// lower ones) or `None`.
    fn walk<V: Visit<T>>(cfg: &Self::Config, w: &mut Walk<'_, T, Self, V>) -> Self;
}

fn make<T: Copy, R: Record<T>>(cfg: &R::Config, visit: impl Visit<T>) -> R {
    R::walk(
        cfg,
        &mut Walk {
            from: None,
            visit,
            value: PhantomData,
        },
    )
}

fn read<T: Copy, R: Record<T>>(cfg: &R::Config, rec: &R, visit: impl Visit<T>) {
    R::walk(
        cfg,
        &mut Walk {
            from: Some(rec),
            visit,
            value: PhantomData,
        },
    );
}

/// The ports of record type `R` in `cfg`, in port order: name and type
/// (`R` is the record of `()`, e.g. `SilhouetteIn<()>`).
pub fn list<R: Record<()>>(cfg: &R::Config) -> Vec<(String, Ty)> {
    let mut ports = Vec::new();
    make::<(), R>(cfg, |name, ty, _| ports.push((name.to_string(), ty)));
    ports
}

/// Declares the record's ports as the module's inputs, in port order.
pub fn declare_inputs<R: Record<Sig>>(m: &mut ModuleBuilder, cfg: &R::Config) -> R {
    make(cfg, |name, ty, _| m.input(&name.to_string(), ty))
}

/// Declares the record's values as the module's outputs, in port order.
/// Panics if a value's type is not its port's (a generator bug).
pub fn declare_outputs<R: Record<Sig>>(m: &mut ModuleBuilder, cfg: &R::Config, outputs: &R) {
    read(cfg, outputs, |name, ty, value| {
        let value = value.expect("reading a record gives every value");
        assert_eq!(value.ty(), ty, "output `{name}` has the wrong type");
        m.output(&name.to_string(), value);
        value
    })
}

/// The record's ports by name with their values, in port order: the
/// connections of an instance of a module whose inputs the record declared.
pub fn connections<R: Record<Sig>>(cfg: &R::Config, rec: &R) -> Vec<(String, Sig)> {
    let mut named = Vec::new();
    read(cfg, rec, |name, _, value| {
        let value = value.expect("reading a record gives every value");
        named.push((name.to_string(), value));
        value
    });
    named
}

/// Instantiates `module` as `inst`, its inputs connected from the record
/// `inputs` and its outputs read into a record: both records are the ones
/// the module declared its ports with, so no port is named twice. Its
/// outputs belong to the stage `module.latency` cycles after the current
/// one. A port the module lacks, or of another type, is a generator bug
/// (the builder reports an unconnected input; an output panics here).
#[track_caller]
pub fn instance<I: Record<Sig>, O: Record<Sig>>(
    m: &mut ModuleBuilder,
    inst: &str,
    module: &Arc<Module>,
    inputs_cfg: &I::Config,
    inputs: &I,
    outputs_cfg: &O::Config,
) -> O {
    let outs = m.instance(inst, module, &connections(inputs_cfg, inputs));
    let mut k = 0;
    make(outputs_cfg, |name, ty, _| {
        let (port, _) = &module.outputs[k];
        assert!(
            port.name == name.to_string() && port.ty == ty,
            "{inst}: output {k} of {} is {} {}, the record says {name} {ty}",
            module.name,
            port.name,
            port.ty
        );
        k += 1;
        outs.all()[k - 1]
    })
}

/// Writes the record's words into `words` in port order (a vector's inputs,
/// or the golden model's outputs).
pub fn pack<R: Record<u64>>(cfg: &R::Config, rec: &R, words: &mut [u64]) {
    let mut k = 0;
    read(cfg, rec, |_, _, value| {
        let value = value.expect("reading a record gives every value");
        words[k] = value;
        k += 1;
        value
    })
}

/// The record whose ports take `value(ty)`, called once per port in port
/// order (random words of each port's width, positions, a vector's words).
pub fn from_fn<T: Copy, R: Record<T>>(cfg: &R::Config, mut value: impl FnMut(Ty) -> T) -> R {
    make(cfg, |_, ty, _| value(ty))
}

/// Where each field's port is: the record of the ports' positions in port
/// order.
pub fn positions<R: Record<usize>>(cfg: &R::Config) -> R {
    let mut k = 0;
    from_fn(cfg, |_| {
        k += 1;
        k - 1
    })
}

/// The record of the words in `words`, in port order.
pub fn unpack<R: Record<u64>>(cfg: &R::Config, words: &[u64]) -> R {
    let mut k = 0;
    from_fn(cfg, |_| {
        k += 1;
        words[k - 1]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::silhouette::{Config, Mode, Origin, Policy, SilhouetteIn, SilhouetteOut};

    fn cfg(mode: Mode, origin: Origin) -> Config {
        Config {
            fmt: crate::arith::float::Format::new(5, 4).unwrap(),
            mode,
            origin,
            policy: Policy::Conservative,
            stages: 2,
        }
    }

    fn names<R: Record<()>>(c: &R::Config) -> Vec<String> {
        list::<R>(c).into_iter().map(|(n, _)| n).collect()
    }

    /// One walk gives the names, the positions and the packing: a ray's
    /// upper bounds are its lower ones, a shared origin has no `o_hi`.
    #[test]
    fn names_positions_and_packing_follow_one_walk() {
        let ray = cfg(Mode::Ray, Origin::Shared);
        let names_ray = names::<SilhouetteIn<()>>(&ray);
        assert_eq!(names_ray.len(), 14);
        assert_eq!(&names_ray[6..9], ["o_x", "o_y", "o_z"]);
        assert_eq!(names_ray[13], "t_max");
        let at: SilhouetteIn<usize> = positions(&ray);
        assert_eq!((at.o_lo, at.o_hi), ([6, 7, 8], [6, 7, 8]));
        assert_eq!((at.d_lo, at.d_hi), ([9, 10, 11], [9, 10, 11]));
        assert_eq!(at.t_min, 12);

        let bounded = cfg(Mode::Bundle, Origin::Bounded);
        assert_eq!(names::<SilhouetteIn<()>>(&bounded).len(), 20);
        let shared = cfg(Mode::Bundle, Origin::Shared);
        let words: Vec<u64> = (100..117).collect();
        let rec: SilhouetteIn<u64> = unpack(&shared, &words);
        assert_eq!(rec.o_hi, rec.o_lo);
        assert_eq!(rec.d_hi, [112, 113, 114]);
        let mut again = vec![0; words.len()];
        pack(&shared, &rec, &mut again);
        assert_eq!(again, words);

        let outs = names::<SilhouetteOut<()>>(&ray);
        assert_eq!(outs, ["hit", "nan", "invalid"]);
        let out: SilhouetteOut<u64> = unpack(&ray, &[1, 0, 1]);
        assert_eq!((out.any_hit, out.all_hit, out.invalid), (1, None, 1));
    }

    /// An output of another type than its port's is a generator bug.
    #[test]
    #[should_panic(expected = "output `hit` has the wrong type")]
    fn an_output_of_the_wrong_type_panics() {
        let ray = cfg(Mode::Ray, Origin::Shared);
        let mut m = ModuleBuilder::new("wrong");
        let x = m.input("x", Ty::UInt(3));
        let out = SilhouetteOut {
            all_hit: None,
            any_hit: x,
            nan: x,
            invalid: x,
            mixed_sign: None,
        };
        declare_outputs(&mut m, &ray, &out);
    }
}
