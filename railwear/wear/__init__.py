"""Wear laws with internal state and their distribution over the contact patch (layer 1)."""
