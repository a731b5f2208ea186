//! sensor (being written).
