//! Verilator driver, vector format and cross-check.
