//! Arithmetic operators built from the DSL's primitives. Each generator adds
//! logic to the module being built, or builds a module of its own to be
//! instantiated; none touches the emitter.

pub mod float;
pub mod int;
pub mod ports;
pub mod recip;
