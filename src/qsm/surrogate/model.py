"""Stage 3: the MLP surrogate from the 6 scaled lengths to (eta, tau1, tau2) (paper Section 2.3).

scikit-learn's ``MLPRegressor`` is trained on min-max normalised inputs and outputs (optionally on
log outputs). The trained network is stored without pickle, as plain arrays in JSON, and evaluated
by :class:`Surrogate` with numpy (the same arithmetic as scikit-learn's forward pass).
"""

from __future__ import annotations

import json
import logging
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from sklearn.exceptions import ConvergenceWarning
from sklearn.metrics import mean_squared_error, r2_score
from sklearn.model_selection import train_test_split
from sklearn.neural_network import MLPRegressor

from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.schema.defaults import default

LOG = logging.getLogger(__name__)

INPUTS: tuple[str, ...] = DESIGN_COLUMNS
OUTPUTS: tuple[str, ...] = ("eta", "tau1_Nm", "tau2_Nm")
SHORT: dict[str, str] = {"eta": "eta", "tau1_Nm": "tau1", "tau2_Nm": "tau2"}
FORMAT = "qsm-surrogate/1"
OUTPUT_TRANSFORMS: tuple[str, ...] = ("none", "log")


@dataclass(frozen=True)
class SurrogateSettings:
    """Network and training settings (config section ``surrogate``)."""

    hidden_layers: tuple[int, ...] = default("surrogate.hidden_layers")
    learning_rate: float = default("surrogate.learning_rate")
    max_epochs: int = default("surrogate.max_epochs")
    tol: float = default("surrogate.tol")
    n_iter_no_change: int = default("surrogate.n_iter_no_change")
    early_stopping: bool = default("surrogate.early_stopping")
    alpha: float = default("surrogate.alpha")
    batch_size: int = default("surrogate.batch_size")
    output_transform: str = default("surrogate.output_transform")
    test_fraction: float = default("surrogate.test_fraction")
    seed: int = default("surrogate.seed")

    def __post_init__(self) -> None:
        if self.output_transform not in OUTPUT_TRANSFORMS:
            raise ValueError(
                f"surrogate.output_transform: {self.output_transform!r} is not one of "
                f"{', '.join(OUTPUT_TRANSFORMS)}"
            )


@dataclass(frozen=True)
class Surrogate:
    """A trained MLP with its normalisation; ``predict`` maps (N, 6) lengths (m) to (N, 3)."""

    x_min: NDArray[np.float64]
    x_span: NDArray[np.float64]
    y_min: NDArray[np.float64]
    y_span: NDArray[np.float64]
    output_transform: str
    weights: tuple[NDArray[np.float64], ...]
    biases: tuple[NDArray[np.float64], ...]
    label_mean: NDArray[np.float64]  # of the training labels, physical units (constraints g5..g10)
    label_std: NDArray[np.float64]

    def predict_normalized(self, x: ArrayLike) -> NDArray[np.float64]:
        """Network output (normalised, transformed targets) for raw inputs (N, 6) in metres."""
        h = (np.atleast_2d(np.asarray(x, dtype=float)) - self.x_min) / self.x_span
        for i, (w, b) in enumerate(zip(self.weights, self.biases, strict=True)):
            h = h @ w + b
            if i < len(self.weights) - 1:
                h = np.maximum(h, 0.0)
        return h

    def predict(self, x: ArrayLike) -> NDArray[np.float64]:
        """(eta, tau1 in Nm, tau2 in Nm) for designs (N, 6) of scaled lengths in metres."""
        y = self.predict_normalized(x) * self.y_span + self.y_min
        return np.exp(y) if self.output_transform == "log" else y

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": FORMAT,
            "inputs": list(INPUTS),
            "outputs": list(OUTPUTS),
            "x_min": self.x_min.tolist(),
            "x_span": self.x_span.tolist(),
            "y_min": self.y_min.tolist(),
            "y_span": self.y_span.tolist(),
            "output_transform": self.output_transform,
            "weights": [w.tolist() for w in self.weights],
            "biases": [b.tolist() for b in self.biases],
            "label_mean": self.label_mean.tolist(),
            "label_std": self.label_std.tolist(),
        }

    def save(self, path: str | Path) -> None:
        """Write the model as JSON (no pickle)."""
        Path(path).write_text(json.dumps(self.to_dict()))


def load(path: str | Path) -> Surrogate:
    """Read a surrogate written by :meth:`Surrogate.save`."""
    try:
        data = json.loads(Path(path).read_text())
    except (OSError, json.JSONDecodeError) as exc:
        raise ValueError(f"cannot read surrogate '{path}': {exc}") from exc
    if data.get("format") != FORMAT:
        raise ValueError(f"'{path}' is not a {FORMAT} file")
    arr = np.asarray
    return Surrogate(
        x_min=arr(data["x_min"]),
        x_span=arr(data["x_span"]),
        y_min=arr(data["y_min"]),
        y_span=arr(data["y_span"]),
        output_transform=data["output_transform"],
        weights=tuple(arr(w) for w in data["weights"]),
        biases=tuple(arr(b) for b in data["biases"]),
        label_mean=arr(data["label_mean"]),
        label_std=arr(data["label_std"]),
    )


def _span(values: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    lo = values.min(axis=0)
    return lo, np.where(values.max(axis=0) > lo, values.max(axis=0) - lo, 1.0)


def regression_metrics(
    y_true: NDArray[np.float64], y_pred: NDArray[np.float64], y_min: NDArray, y_span: NDArray
) -> dict[str, dict[str, float]]:
    """R^2, MSE and RMSE per output and over all outputs ("all", as the paper's Table 2).

    MSE and RMSE are on outputs min-max normalised by the training labels (so comparable across
    outputs and with the paper); R^2 does not depend on the normalisation. "all" is the mean R^2 of
    the outputs and the MSE over every normalised value.
    """
    t = (y_true - y_min) / y_span
    p = (y_pred - y_min) / y_span
    out: dict[str, dict[str, float]] = {"r2": {}, "mse": {}, "rmse": {}}
    for j, name in enumerate(OUTPUTS):
        key = SHORT[name]
        out["r2"][key] = float(r2_score(t[:, j], p[:, j]))
        out["mse"][key] = float(mean_squared_error(t[:, j], p[:, j]))
        out["rmse"][key] = float(np.sqrt(out["mse"][key]))
    out["r2"]["all"] = float(r2_score(t, p))
    out["mse"]["all"] = float(mean_squared_error(t, p))
    out["rmse"]["all"] = float(np.sqrt(out["mse"]["all"]))
    return out


@dataclass(frozen=True)
class Training:
    """A trained surrogate, its metrics, the test rows and the fit time."""

    model: Surrogate
    metrics: dict[str, Any]
    test_index: NDArray[np.int64]
    test_prediction: NDArray[np.float64]
    estimator: MLPRegressor


def training_rows(n: int, settings: SurrogateSettings) -> tuple[NDArray, NDArray]:
    """The seeded train and test rows of ``n`` designs: the split :func:`train` makes."""
    return train_test_split(
        np.arange(n), test_size=settings.test_fraction, random_state=settings.seed
    )


def _network(settings: SurrogateSettings) -> MLPRegressor:
    """An untrained MLP of ``settings`` (ReLU, Adam, seeded)."""
    return MLPRegressor(
        hidden_layer_sizes=settings.hidden_layers,
        activation="relu",
        solver="adam",
        learning_rate_init=settings.learning_rate,
        max_iter=settings.max_epochs,
        tol=settings.tol,
        n_iter_no_change=settings.n_iter_no_change,
        early_stopping=settings.early_stopping,
        alpha=settings.alpha,
        batch_size=settings.batch_size,
        random_state=settings.seed,
    )


def _target(y: NDArray[np.float64], settings: SurrogateSettings) -> NDArray[np.float64]:
    """The labels as the network learns them (log where ``output_transform`` says)."""
    if settings.output_transform == "log" and np.any(y <= 0):
        raise ValueError("surrogate.output_transform 'log' needs positive labels")
    return np.log(y) if settings.output_transform == "log" else y


def _fitted(
    mlp: MLPRegressor,
    scaling: tuple[NDArray, NDArray, NDArray, NDArray],
    x: NDArray[np.float64],
    y: NDArray[np.float64],
    settings: SurrogateSettings,
    epochs: int | None = None,
) -> tuple[Surrogate, float]:
    """Fit ``mlp`` on designs ``x`` and labels ``y`` normalised by ``scaling`` (x_min, x_span,
    t_min, t_span): to convergence, or ``epochs`` passes from the weights it has; the model and
    the fit time (s)."""
    x_min, x_span, t_min, t_span = scaling
    inputs, outputs = (x - x_min) / x_span, (_target(y, settings) - t_min) / t_span
    start = time.perf_counter()
    if epochs is None:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", ConvergenceWarning)
            mlp.fit(inputs, outputs)
        if any(issubclass(w.category, ConvergenceWarning) for w in caught):
            LOG.info(
                "the MLP stopped at its %d epochs before its loss settled (surrogate.max_epochs): "
                "its test errors say what it reached", mlp.max_iter,
            )  # fmt: skip
    else:
        for _ in range(epochs):  # further epochs from its weights (shuffled by its own seed)
            mlp.partial_fit(inputs, outputs)
    seconds = time.perf_counter() - start
    model = Surrogate(
        x_min=x_min,
        x_span=x_span,
        y_min=t_min,
        y_span=t_span,
        output_transform=settings.output_transform,
        weights=tuple(np.array(w, copy=True) for w in mlp.coefs_),  # a later warm start
        biases=tuple(np.array(b, copy=True) for b in mlp.intercepts_),  # trains mlp in place
        label_mean=y.mean(axis=0),
        label_std=y.std(axis=0),
    )
    return model, seconds


def train(x: ArrayLike, y: ArrayLike, settings: SurrogateSettings) -> Training:
    """Fit the MLP on a seeded train/test split of designs ``x`` (N, 6) and labels ``y`` (N, 3)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    train_idx, test_idx = training_rows(len(x), settings)
    target = _target(y, settings)
    scaling = (*_span(x[train_idx]), *_span(target[train_idx]))
    mlp = _network(settings)
    model, seconds = _fitted(mlp, scaling, x[train_idx], y[train_idx], settings)
    y_min, y_span = _span(y[train_idx])
    pred_train = model.predict(x[train_idx])
    metrics = {
        "train": regression_metrics(y[train_idx], pred_train, y_min, y_span),
        "test": regression_metrics(y[test_idx], model.predict(x[test_idx]), y_min, y_span),
        "fit_seconds": seconds,
        "epochs": int(mlp.n_iter_),
        "n_train": len(train_idx),
        "n_test": len(test_idx),
    }
    test_idx = np.sort(test_idx)
    return Training(model, metrics, test_idx, model.predict(x[test_idx]), mlp)


def refit(
    x: ArrayLike,
    y: ArrayLike,
    settings: SurrogateSettings,
    previous: Training | None = None,
    span: tuple[ArrayLike, ArrayLike] | None = None,
) -> Training:
    """The MLP fitted on every row of designs ``x`` (N, 6) and labels ``y`` (N, 3), no split
    (the adaptive infill's: its designs' errors are measured before they join). Warm-started
    from ``previous`` where its normalisation holds every row (the network then sees the same
    inputs) and ``early_stopping`` is off: ``n_iter_no_change`` further epochs from its weights;
    else from scratch, seeded, normalised over the designs and labels ``span`` (a superset of
    ``x`` and ``y``: then refits on different subsets of it share a normalisation, and the next
    can warm-start) or over ``x`` and ``y``."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    target = _target(y, settings)
    span_x, span_y = (x, y) if span is None else (np.asarray(a, dtype=float) for a in span)
    # partial_fit cannot hold out a validation split: with early_stopping, always afresh
    warm = previous is not None and not settings.early_stopping
    warm = warm and _holds(previous.model, x, target)
    if warm:
        mlp, m = previous.estimator, previous.model
        scaling = (m.x_min, m.x_span, m.y_min, m.y_span)
        model, seconds = _fitted(mlp, scaling, x, y, settings, settings.n_iter_no_change)
    else:
        mlp, scaling = _network(settings), (*_span(span_x), *_span(_target(span_y, settings)))
        model, seconds = _fitted(mlp, scaling, x, y, settings)
    # partial_fit restarts sklearn's n_iter_ count: the warm epochs are the ones run here
    epochs = settings.n_iter_no_change if warm else int(mlp.n_iter_)
    metrics = {"fit_seconds": seconds, "epochs": epochs, "n_train": len(x), "warm_start": warm}
    return Training(model, metrics, np.zeros(0, np.int64), np.zeros((0, y.shape[1])), mlp)


def _holds(model: Surrogate, x: NDArray[np.float64], target: NDArray[np.float64]) -> bool:
    """Whether ``model``'s min-max normalisation maps every row into [0, 1]."""
    inside = [
        ((v - lo) >= -1e-12).all() and ((v - lo) <= span + 1e-12).all()
        for v, lo, span in ((x, model.x_min, model.x_span), (target, model.y_min, model.y_span))
    ]
    return all(inside)


def metrics_markdown(metrics: Mapping[str, Any]) -> str:
    """The metrics as a Markdown table like the paper's Table 2, one row per split and output."""
    lines = ["| split | output | R^2 | MSE | RMSE |", "| --- | --- | --- | --- | --- |"]
    for split in ("train", "test"):
        m = metrics[split]
        for key in (*SHORT.values(), "all"):
            lines.append(
                f"| {split} | {key} | {m['r2'][key]:.5f} | {m['mse'][key]:.5f} | "
                f"{m['rmse'][key]:.5f} |"
            )
    lines.append("")
    lines.append(
        f"Fit: {metrics['fit_seconds']:.1f} s, {metrics['epochs']} epochs, "
        f"{metrics['n_train']} training and {metrics['n_test']} test designs. MSE and RMSE on "
        "outputs min-max normalised by the training labels."
    )
    return "\n".join(lines) + "\n"
