"""Long-term strategies over one wheel state (layer 3)."""
