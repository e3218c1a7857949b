//! Potential fields by the method of fundamental solutions (the paper's Sections 2–4).
