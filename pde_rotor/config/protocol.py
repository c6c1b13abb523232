"""The stop-and-release section: the run's own, and each body's where it has one."""

from __future__ import annotations

from typing import Annotated

from pydantic import Field, model_validator

from .errors import FieldError
from .fields import CYCLES_BOUND, TIME_BOUND, Int, NonNegativeFloat, PositiveFloat, _Section
from .recorded import BuiltInto


class ProtocolConfig(_Section):
    """Stop-and-release operations (paper section "Model", last part)."""

    t_ini: Annotated[NonNegativeFloat, BuiltInto("n_ini")] = Field(
        10.0, le=TIME_BOUND, description="t_ini: free rotation before the first stop"
    )
    t_stop: Annotated[NonNegativeFloat, BuiltInto("n_stop")] = Field(
        0.5, le=TIME_BOUND, description="t_stop: duration of one forced stop"
    )
    t_release: Annotated[PositiveFloat, BuiltInto("n_period")] = Field(
        10.0, le=TIME_BOUND, description="t_release: free rotation after a stop"
    )
    cycles: Int = Field(
        100, ge=0, le=CYCLES_BOUND, description="M: number of stop-and-release cycles"
    )

    @property
    def period(self) -> float:
        """Cycle period T = t_stop + t_release."""
        return self.t_stop + self.t_release

    @property
    def t_end(self) -> float:
        """End of the protocol, t_ini + M T."""
        return self.t_ini + self.cycles * self.period

    @model_validator(mode="after")
    def _something_to_run(self) -> ProtocolConfig:
        if self.t_end <= 0:
            msg = "nothing to simulate: t_ini + cycles * (t_stop + t_release) = 0 (allowed: > 0)"
            raise FieldError("t_ini", self.t_ini, msg)
        return self
