"""Multi-sensor ranked-assignment problems and samplers (spec ``multisensor.md``)."""

from .adaptive_birth import AdaptiveBirthProblem, BirthLMB, birth_from_samples

__all__ = ["AdaptiveBirthProblem", "BirthLMB", "birth_from_samples"]
