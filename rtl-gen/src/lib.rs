//! rtl-gen: the DSL.
