"""The design optimiser: maximise range over the paper's design variables within its size limits."""
