"""Grading at scale: the container image (``Containerfile``), the Kubernetes Job
(``grade-job.yaml``) and its shard runner (``grade_shard.py``); ``book/grading-at-scale.md``."""
