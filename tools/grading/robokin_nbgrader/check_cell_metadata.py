"""``RobokinCheckCellMetadata`` (every pipeline, replaces ``CheckCellMetadata``).

nbgrader's check of the cells' nbgrader metadata, with nbgrader's schema checked once per
process instead of once per cell (the same verdicts).
"""

from __future__ import annotations

import traceback
from typing import Any

import jsonschema
from nbgrader.nbgraderformat import MetadataValidator, ValidationError
from nbgrader.nbgraderformat.common import BaseMetadataValidator
from nbgrader.preprocessors import CheckCellMetadata


class _SchemaCheckedOnce(BaseMetadataValidator):
    """nbgrader's per-cell check of the metadata against its schema, with the schema itself checked
    once per process: ``jsonschema.validate``, which nbgrader calls for every cell, first checks
    nbgrader's own (constant) schema against the JSON meta-schema -- nine tenths of the time
    ``CheckCellMetadata`` takes. A cell's metadata is then validated as ``jsonschema.validate``
    does it (the same best-matching error); a cell without metadata, or of another schema version
    (an error), goes to nbgrader's own code."""

    _validators: dict[int, Any] = {}   # jsonschema validators, per schema version

    def validate_cell(self, cell) -> None:
        meta = cell.metadata.get("nbgrader")
        if meta is None or meta.get("schema_version", 0) != self.schema_version:
            return super().validate_cell(cell)
        validator = self._validators.get(self.schema_version)
        if validator is None:
            cls = jsonschema.validators.validator_for(self.schema)
            cls.check_schema(self.schema)
            validator = self._validators[self.schema_version] = cls(self.schema)
        error = jsonschema.exceptions.best_match(validator.iter_errors(meta))
        if error is not None:
            raise error
        return None


class _MetadataValidator(MetadataValidator, _SchemaCheckedOnce):
    """nbgrader's metadata validator (its checks beyond the schema included), the schema
    checked once per process (:class:`_SchemaCheckedOnce` comes between it and its base)."""


class RobokinCheckCellMetadata(CheckCellMetadata):
    """nbgrader's ``CheckCellMetadata`` (the same verdicts, errors and messages), with the schema
    checked once per process instead of once per cell (:class:`_SchemaCheckedOnce`)."""

    def preprocess(self, nb, resources):
        try:
            _MetadataValidator().validate_nb(nb)
        except ValidationError:
            self.log.error(traceback.format_exc())
            msg = "Notebook failed to validate; the nbgrader metadata may be corrupted."
            self.log.error(msg)
            raise ValidationError(msg)  # noqa: B904 - as nbgrader's CheckCellMetadata raises it
        return nb, resources
