"""Multi-sensor ranked assignment (spec ``multisensor.md``): problem, samplers."""
