"""The MLP surrogate: storage without pickle, metrics, and the paper's settings."""

import json
import logging
import warnings

import numpy as np
import pytest

from qsm.config.reading import load_config
from qsm.config.settings import surrogate
from qsm.surrogate.model import (
    Surrogate,
    SurrogateSettings,
    load,
    metrics_markdown,
    refit,
    regression_metrics,
    train,
)


@pytest.fixture(scope="module")
def fitted():
    rng = np.random.default_rng(0)
    x = rng.uniform(0.1, 1.0, (1500, 6))
    y = np.column_stack(
        [
            0.05 + x[:, 0] * x[:, 1],
            40 + 20 * x[:, 4] ** 2 + 5 * x[:, 0],
            15 + 5 * np.sin(3 * x[:, 2]),
        ]
    )
    settings = SurrogateSettings(max_epochs=400, seed=3)
    return x, y, settings, train(x, y, settings)


def test_paper_settings_are_the_defaults():
    s = surrogate.surrogate(load_config()["surrogate"])
    assert s.hidden_layers == (100,) and s.learning_rate == 1e-3 and s.max_epochs == 50_000


def test_forward_pass_equals_scikit_learn(fitted):
    x, _, _, result = fitted
    model = result.model
    normalized = (x - model.x_min) / model.x_span
    np.testing.assert_allclose(
        model.predict_normalized(x), result.estimator.predict(normalized), rtol=1e-12, atol=1e-12
    )


def test_json_round_trip_without_pickle(fitted, tmp_path):
    x, _, _, result = fitted
    path = tmp_path / "model.json"
    result.model.save(path)
    assert json.loads(path.read_text())["format"] == "qsm-surrogate/1"
    again = load(path)
    assert isinstance(again, Surrogate)
    np.testing.assert_array_equal(again.predict(x), result.model.predict(x))
    np.testing.assert_array_equal(again.label_std, result.model.label_std)
    (tmp_path / "bad.json").write_text("{}")
    with pytest.raises(ValueError, match=r"bad\.json"):
        load(tmp_path / "bad.json")


def test_learns_a_smooth_function_and_reports_the_paper_table(fitted):
    x, y, settings, result = fitted
    m = result.metrics
    assert set(m) >= {"train", "test", "fit_seconds"}
    for split in ("train", "test"):
        for metric in ("r2", "mse", "rmse"):
            assert set(m[split][metric]) == {"eta", "tau1", "tau2", "all"}
    assert min(m["test"]["r2"].values()) > 0.98
    assert len(result.test_index) == round(settings.test_fraction * len(x))
    # the stored label statistics are those of the training rows only
    train_rows = np.setdiff1d(np.arange(len(x)), result.test_index)
    np.testing.assert_allclose(result.model.label_mean, y[train_rows].mean(axis=0))
    assert "| test | all |" in metrics_markdown(m)


def test_metrics_by_hand():
    truth = np.array([[0.0, 0.0, 0.0], [1.0, 2.0, 4.0]])
    pred = np.array([[0.0, 0.5, 0.0], [1.0, 2.0, 3.0]])
    m = regression_metrics(truth, pred, np.zeros(3), np.array([1.0, 2.0, 4.0]))
    # normalised errors: eta 0, 0; tau1 0.25, 0; tau2 0, -0.25
    assert m["mse"]["eta"] == 0 and m["r2"]["eta"] == 1
    assert m["mse"]["tau1"] == pytest.approx(0.25**2 / 2)
    assert m["r2"]["tau2"] == pytest.approx(1 - 0.0625 / 0.5)
    assert m["mse"]["all"] == pytest.approx(2 * 0.0625 / 6)
    assert m["rmse"]["all"] == pytest.approx(np.sqrt(2 * 0.0625 / 6))


def test_same_seed_same_model(fitted):
    x, y, settings, result = fitted
    again = train(x, y, settings)
    np.testing.assert_array_equal(again.model.weights[0], result.model.weights[0])


def test_log_transform_needs_positive_labels():
    x = np.ones((10, 6))
    with pytest.raises(ValueError, match="positive"):
        train(x, -np.ones((10, 3)), SurrogateSettings(output_transform="log"))


def test_unknown_output_transform_is_rejected():
    """'lg' once meant no transform, silently."""
    with pytest.raises(ValueError, match=r"surrogate\.output_transform: 'lg'"):
        SurrogateSettings(output_transform="lg")


def test_the_infill_refit_warm_starts_only_where_the_normalisation_holds():
    """A refit on rows within the last fit's min-max ranges continues from its weights for
    n_iter_no_change epochs; a row outside them (the inputs would move) refits from scratch."""
    rng = np.random.default_rng(0)
    x = rng.uniform(0.0, 1.0, size=(300, 6))
    y = np.column_stack([1 + x[:, 0], 2 + x[:, 1] * x[:, 2], 3 + x[:, 3] ** 2])
    settings = SurrogateSettings(hidden_layers=(16,), max_epochs=200, n_iter_no_change=7, seed=0)
    first = refit(x, y, settings)
    assert not first.metrics["warm_start"] and first.metrics["n_train"] == 300
    before = first.model.predict(x)
    weights = [w.copy() for w in first.model.weights]
    extra = np.full((1, 6), 0.5)
    inside = refit(np.vstack([x, extra]), np.vstack([y, y[:1]]), settings, first)
    assert inside.metrics["warm_start"] and inside.metrics["epochs"] == 7
    np.testing.assert_array_equal(inside.model.x_min, first.model.x_min)
    for w, kept, now in zip(first.model.weights, weights, inside.model.weights, strict=True):
        np.testing.assert_array_equal(w, kept)  # the former model is left as it was
        assert not np.array_equal(now, kept)  # the refit trained on
    after = inside.model.predict(x)  # from its weights, not afresh: close to where it was
    assert np.abs(after - before).max() < 0.05 * np.abs(before).max()
    outside = refit(np.vstack([x, extra + 1.0]), np.vstack([y, y[:1]]), settings, inside)
    assert not outside.metrics["warm_start"]
    assert outside.model.x_span[0] > first.model.x_span[0]


def test_refits_on_subsets_of_one_span_share_its_normalisation_and_warm_start():
    """The infill refits on a bounded subset of the training rows that changes every round:
    normalised over the whole ``span``, the second subset (holding rows beyond the first's
    ranges) keeps the first's normalisation and continues from its weights."""
    rng = np.random.default_rng(2)
    x = rng.uniform(0.0, 1.0, size=(400, 6))
    y = np.column_stack([1 + x[:, 0], 2 + x[:, 1] * x[:, 2], 3 + x[:, 3] ** 2])
    settings = SurrogateSettings(hidden_layers=(16,), max_epochs=200, n_iter_no_change=7, seed=0)
    low, high = np.argsort(x[:, 0])[:250], np.argsort(x[:, 0])[150:]
    first = refit(x[low], y[low], settings, None, (x, y))
    assert not first.metrics["warm_start"] and first.metrics["n_train"] == 250
    np.testing.assert_array_equal(first.model.x_min, x.min(axis=0))
    np.testing.assert_array_equal(first.model.x_span, np.ptp(x, axis=0))
    np.testing.assert_array_equal(first.model.y_span, np.ptp(y, axis=0))
    second = refit(x[high], y[high], settings, first, (x, y))
    assert second.metrics["warm_start"] and second.metrics["epochs"] == 7
    unspanned = refit(x[high], y[high], settings, refit(x[low], y[low], settings))
    assert not unspanned.metrics["warm_start"]  # each subset's own ranges: afresh


def test_with_early_stopping_every_refit_starts_afresh():
    """partial_fit cannot hold out a validation split: with early_stopping on, a refit whose
    normalisation would hold still fits from scratch, and does not fail."""
    rng = np.random.default_rng(1)
    x = rng.uniform(0.0, 1.0, size=(200, 6))
    y = np.column_stack([1 + x[:, 0], 2 + x[:, 1], 3 + x[:, 2]])
    settings = SurrogateSettings(
        hidden_layers=(8,), max_epochs=100, n_iter_no_change=5, early_stopping=True, seed=0
    )
    first = refit(x, y, settings)
    again = refit(x, y, settings, first)
    assert not first.metrics["warm_start"] and not again.metrics["warm_start"]


def test_an_mlp_stopped_by_its_epochs_says_so_in_the_log_not_on_the_console(caplog):
    """scikit-learn's ConvergenceWarning becomes one log line naming surrogate.max_epochs."""
    rng = np.random.default_rng(1)
    x = rng.uniform(0.1, 1.0, (1000, 6))
    y = np.column_stack([0.05 + x[:, 0] * x[:, 1], 40 + 20 * x[:, 4], 15 + 5 * x[:, 2]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing may reach the console
        with caplog.at_level(logging.INFO, logger="qsm.surrogate.model"):
            train(x, y, SurrogateSettings(max_epochs=2, seed=3))
    assert "surrogate.max_epochs" in caplog.text
