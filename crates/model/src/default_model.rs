//! The built-in default model (the paper's subject1 model), shipped in stride's own format.
