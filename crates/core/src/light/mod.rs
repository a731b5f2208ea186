//! light (being written).
