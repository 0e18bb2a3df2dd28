//! RTL in the loop.
