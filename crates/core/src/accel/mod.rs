//! accel (being written).
