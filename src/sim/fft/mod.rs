//! Our inverse 2D FFT (placeholder: being written).
