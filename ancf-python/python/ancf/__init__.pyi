"""Type stubs of the ancf package (units: SI)."""

from os import PathLike
from typing import Any, Callable, Literal, Optional, Union

import numpy as np
import numpy.typing as npt

class SceneError(ValueError):
    """A scene that cannot be run; ``field`` names the field at fault, ``line`` and ``column`` (from 1) locate an error of TOML syntax or type."""

    field: str
    line: Optional[int]
    column: Optional[int]

class SimulationError(RuntimeError):
    """A simulation that could not go on (step, time and likely cause in the message)."""

class PlausibilityWarning(UserWarning):
    """What a scene will likely do badly (a unit slip, an unresolved contact), raised when a scene or a wire is built, or what a run did that its numbers cannot show (a stress past yield), raised when it reaches its end; ``warnings.simplefilter("error")`` makes it an exception."""

class Scene:
    """A validated scene (the same schema and validation as ``ancf check``)."""

    @staticmethod
    def from_file(path: Union[str, PathLike[str]]) -> Scene:
        """Reads and validates a scene file; a file that cannot be read raises FileNotFoundError / PermissionError / OSError."""
        ...
    @staticmethod
    def from_toml(text: str) -> Scene: ...
    @staticmethod
    def from_dict(d: dict[str, Any]) -> Scene: ...
    @property
    def elements(self) -> int: ...
    @property
    def unknowns(self) -> int: ...
    @property
    def kind(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def warnings(self) -> list[str]:
        """Material constants outside the ranges of real materials, and each contact the time step does not resolve (with the step that would)."""
        ...

class Material:
    """A layer material (SI units)."""

    @staticmethod
    def st_venant_kirchhoff(
        density: float,
        youngs_modulus: float,
        poisson_ratio: Optional[float] = None,
        bending_factor: Optional[float] = None,
        yield_stress: Optional[float] = None,
    ) -> Material: ...
    @staticmethod
    def elastic_plastic(
        density: float,
        youngs_modulus: float,
        yield_stress: float,
        poisson_ratio: Optional[float] = None,
        hardening_modulus: Optional[float] = None,
        hardening: Optional[str] = None,
        rate_d: Optional[float] = None,
        rate_q: Optional[float] = None,
    ) -> Material: ...
    @staticmethod
    def mooney_rivlin(density: float, mu10: float, mu01: float, penalty: float) -> Material: ...

class Wire:
    """A wire described in code; every method returns a new Wire (calls chain)."""

    def __init__(self, length: float, elements: int) -> None: ...
    def graded(self, segments: list[tuple[float, int]]) -> Wire: ...
    def placed(self, origin: list[float], direction: list[float]) -> Wire: ...
    def layer(self, material: Material, outer_radius: float) -> Wire: ...
    def bore(self, inner_radius: float) -> Wire: ...
    def member(
        self,
        name: str,
        length: float,
        elements: int,
        origin: list[float],
        direction: list[float],
        layers: list[tuple[Material, float]],
        inner_radius: float = 0.0,
        contact_stiffness: Optional[float] = None,
        friction: float = 0.0,
        restitution: Optional[float] = None,
        restitution_model: Optional[str] = None,
        contact_law: Optional[str] = None,
    ) -> Wire: ...
    def support(self, node: int, kind: str, beam: Optional[str] = None) -> Wire: ...
    def spring(
        self,
        node: int,
        stiffness: list[float],
        rotational_stiffness: float = 0.0,
        damping: float = 0.0,
        torsional_stiffness: float = 0.0,
        beam: Optional[str] = None,
    ) -> Wire: ...
    def kelvin_voigt(self, coefficient: float, beam: Optional[str] = None) -> Wire: ...
    def rayleigh(
        self, mass: float = 0.0, stiffness: float = 0.0, beam: Optional[str] = None
    ) -> Wire: ...
    def gravity(self, acceleration: list[float]) -> Wire: ...
    def load(self, node: int, force: list[float], beam: Optional[str] = None) -> Wire: ...
    def rod(
        self,
        center: list[float],
        axis: list[float],
        radius: float,
        stiffness: float,
        friction: Optional[float] = None,
        length: Optional[float] = None,
        restitution: Optional[float] = None,
        restitution_model: Optional[str] = None,
    ) -> Wire: ...
    def ground(
        self,
        point: list[float],
        normal: list[float],
        stiffness: float,
        friction: Optional[float] = None,
        restitution: Optional[float] = None,
        restitution_model: Optional[str] = None,
        beams: Optional[list[str]] = None,
    ) -> Wire: ...

class RunResult:
    """Records of a run; every attribute is a float64 NumPy array."""

    @property
    def time(self) -> npt.NDArray[np.float64]: ...
    @property
    def tip(self) -> npt.NDArray[np.float64]: ...
    @property
    def kinetic(self) -> npt.NDArray[np.float64]: ...
    @property
    def strain(self) -> npt.NDArray[np.float64]: ...
    @property
    def gravity(self) -> npt.NDArray[np.float64]: ...
    @property
    def total(self) -> npt.NDArray[np.float64]: ...
    @property
    def dissipated(self) -> npt.NDArray[np.float64]: ...
    @property
    def rod_force(self) -> npt.NDArray[np.float64]: ...
    def __len__(self) -> int: ...

class Simulation:
    """A dynamic simulation of a scene, started at its initial state.

    Bit for bit what ``ancf run`` computes for the scene with
    ``checkpoint_every = 0`` (a checkpoint drops the kept Newton matrix, which
    moves results within the Newton tolerance; a Simulation does not checkpoint).
    """

    def __init__(self, scene: Scene) -> None: ...
    @staticmethod
    def from_wire(
        wire: Wire,
        time_step: Union[float, Literal["auto"]],
        end_time: float,
        spectral_radius: Optional[float] = None,
        error_tolerance: Optional[float] = None,
        max_time_step: Optional[float] = None,
    ) -> Simulation: ...
    def step(self) -> None: ...
    def run(
        self,
        until: Optional[float] = None,
        every: int = 1,
        callback: Optional[Callable[[Simulation], Any]] = None,
    ) -> RunResult: ...
    @property
    def time(self) -> float: ...
    @property
    def steps(self) -> tuple[int, int]: ...
    @property
    def nodes(self) -> npt.NDArray[np.float64]: ...
    @property
    def gradients(self) -> npt.NDArray[np.float64]: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]: ...
    @property
    def tip(self) -> npt.NDArray[np.float64]: ...
    @property
    def energies(self) -> dict[str, float]: ...
    @property
    def contact(self) -> list[dict[str, Any]]: ...
    @property
    def supports(self) -> list[dict[str, Any]]: ...
    def summary(self) -> dict[str, Any]: ...

def run(scene: Union[str, PathLike[str], Scene], out: Union[str, PathLike[str]], quiet: bool = True) -> dict[str, Any]: ...
def quadrature(
    inner: float, outer: float, order: int
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
