//! Standard Procedural Databases scenes (placeholder: being written).
