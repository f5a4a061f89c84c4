"""Networks between numpy and the library: a network trained with numpy alone (PyTorch where it is installed) and
written from its weight arrays gives the same outputs in the library as in numpy to 1e-12; a shipped network's
arrays read back; bad arrays refused."""

import os

import numpy as np
import pytest

import contactnn

U0 = 2.0
LOW, HIGH = 0.1, 0.9


def forward(weights, thresholds, x):
    """Eqs 12-13 in numpy: U = W I - theta, O = 1 / (1 + exp(-2 U / U0)); every layer's activations."""
    layers = [x]
    for w, t in zip(weights, thresholds):
        layers.append(1.0 / (1.0 + np.exp(-2.0 * (layers[-1] @ w.T - t) / U0)))
    return layers


def numpy_predict(weights, thresholds, scaling, features):
    """The library's prediction written out: inputs scaled to [-1, 1], the network, outputs unscaled."""
    gain = 2.0 / (scaling["input_max"] - scaling["input_min"])
    x = np.clip((features - scaling["input_min"]) * gain - 1.0, -1e6, 1e6)
    o = forward(weights, thresholds, x)[-1]
    out_gain = (HIGH - LOW) / (scaling["output_max"] - scaling["output_min"])
    return scaling["output_min"] + (o - LOW) / out_gain


def train(features, targets, scaling, hidden=6, epochs=300, rate=0.5, seed=3):
    """A tiny network trained by full-batch gradient descent on the squared error of the scaled targets."""
    rng = np.random.default_rng(seed)
    sizes = [features.shape[1], hidden, targets.shape[1]]
    weights = [rng.uniform(-1, 1, (sizes[l + 1], sizes[l])) for l in range(2)]
    thresholds = [rng.uniform(-0.1, 0.1, sizes[l + 1]) for l in range(2)]
    gain = 2.0 / (scaling["input_max"] - scaling["input_min"])
    x = (features - scaling["input_min"]) * gain - 1.0
    t = LOW + (targets - scaling["output_min"]) * (HIGH - LOW) / (scaling["output_max"] - scaling["output_min"])
    first = None
    for _ in range(epochs):
        a = forward(weights, thresholds, x)
        error = np.mean((a[-1] - t) ** 2)
        first = error if first is None else first
        delta = (a[-1] - t) * (2.0 / U0) * a[-1] * (1 - a[-1])
        for l in (1, 0):
            grad_w = delta.T @ a[l] / len(x)
            grad_t = -delta.mean(axis=0)
            if l > 0:
                delta = (delta @ weights[l]) * (2.0 / U0) * a[l] * (1 - a[l])
            weights[l] -= rate * grad_w
            thresholds[l] -= rate * grad_t
    assert error < first, "the training did not reduce the error"
    return weights, thresholds


@pytest.fixture(scope="module")
def problem():
    rng = np.random.default_rng(7)
    features = rng.uniform(-1.5, 1.5, (400, 8))
    targets = np.column_stack([np.tanh(features[:, 5]), np.tanh(features[:, 6] - 0.3 * features[:, 7])])
    scaling = {"input_min": features.min(axis=0), "input_max": features.max(axis=0),
               "output_min": np.full(2, -1.0), "output_max": np.full(2, 1.0)}
    return features, targets, scaling


def torch_or_numpy(features, targets, scaling):
    """Weights trained by PyTorch when it is installed (scripts/setup --bench), else by numpy."""
    try:
        import torch  # noqa: F401
    except ImportError:
        return train(features, targets, scaling)
    import torch
    torch.manual_seed(0)
    gain = 2.0 / (scaling["input_max"] - scaling["input_min"])
    x = torch.tensor((features - scaling["input_min"]) * gain - 1.0)
    t = torch.tensor(LOW + (targets + 1.0) * (HIGH - LOW) / 2.0)
    layers = [torch.nn.Linear(8, 6).double(), torch.nn.Linear(6, 2).double()]
    optimiser = torch.optim.SGD([p for l in layers for p in l.parameters()], lr=0.5)
    for _ in range(300):
        optimiser.zero_grad()
        o = x
        for layer in layers:
            o = torch.sigmoid(2.0 * layer(o) / U0)
        loss = torch.mean((o - t) ** 2)
        loss.backward()
        optimiser.step()
    # torch's bias b enters as U = W I + b: the library's threshold is theta = -b.
    return ([l.weight.detach().numpy().copy() for l in layers], [-l.bias.detach().numpy().copy() for l in layers])


def test_written_network_is_numpys(problem, tmp_path):
    features, targets, scaling = problem
    weights, thresholds = torch_or_numpy(features, targets, scaling)
    path = tmp_path / "net.h5"
    network = contactnn.write_network(path, weights, thresholds, u0=U0, target_low=LOW, target_high=HIGH, **scaling)
    read = contactnn.read_network(str(path))
    assert read.layer_sizes == [8, 6, 2] and read.real_type == "float64" and read.surface == "bilinear"
    for a, b in zip(read.weights + read.thresholds, weights + thresholds):
        assert np.array_equal(a, b)
    queries = np.random.default_rng(11).uniform(-2.0, 2.0, (1000, 8))
    expected = numpy_predict(weights, thresholds, scaling, queries)
    for net in (network, read):
        got = net.evaluate(queries)
        assert got.shape == (1000, 2)
        assert np.max(np.abs(got - expected)) <= 1e-12
    # The same weights as a float32 network: the library's float forward pass, to float's precision.
    single = contactnn.make_network(weights, thresholds, u0=U0, real_type="float32", **scaling)
    assert single.real_type == "float32"
    assert np.max(np.abs(single.evaluate(queries) - expected)) <= 1e-5


def test_network_in_a_local_search(problem):
    """A numpy network drives LocalSearch's network method: each query's estimate is the network's output on the
    query's features (here a unit square in the frame of SPEC 4, so the features are the raw coordinates)."""
    features, targets, scaling = problem
    weights, thresholds = train(features, targets, scaling, epochs=50)
    network = contactnn.make_network(weights, thresholds, u0=U0, **scaling)
    search = contactnn.LocalSearch("bilinear", "network", network=network)
    raw = np.array([[0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.4, 0.3, 0.1]])
    param, gap, status = search.run(raw)
    f = np.array([[1, 1, 0, 0, 1, 0.4, 0.3, 0.1]], float)  # xc yc zc xd yd xs ys zs
    assert np.allclose(param, numpy_predict(weights, thresholds, scaling, f), atol=1e-12)


def test_shipped_network_arrays(source_dir):
    network = contactnn.read_network(os.path.join(source_dir, "data", "weights", "bilinear-8.h5"))
    assert network.real_type == "float32" and network.surface == "bilinear"
    sizes = network.layer_sizes
    assert [w.shape for w in network.weights] == [(sizes[l + 1], sizes[l]) for l in range(len(sizes) - 1)]
    scaling = network.scaling
    assert scaling["input_features"] == "paper" and len(scaling["input_min"]) == sizes[0]
    f = np.random.default_rng(2).uniform(-0.5, 0.5, (50, sizes[0]))
    # numpy with the file's (float32) weights in double: the library computes in float, so to float's precision.
    expected = numpy_predict_with(network, f)
    assert np.max(np.abs(network.evaluate(f) - expected)) <= 1e-5


def numpy_predict_with(network, features):
    global U0, LOW, HIGH
    saved = U0, LOW, HIGH
    U0, LOW, HIGH = network.u0, network.scaling["target_low"], network.scaling["target_high"]
    try:
        return numpy_predict(network.weights, network.thresholds, network.scaling, features)
    finally:
        U0, LOW, HIGH = saved


def test_bad_network_arrays(problem, tmp_path):
    features, targets, scaling = problem
    w = [np.zeros((6, 8)), np.zeros((2, 6))]
    t = [np.zeros(6), np.zeros(2)]
    with pytest.raises(ValueError, match=r"weights\[1\]: shape \(2, 5\), expected 6 columns"):
        contactnn.make_network([w[0], np.zeros((2, 5))], t, **scaling)
    with pytest.raises(ValueError, match=r"thresholds\[0\]: shape \(5,\), expected \(6,\)"):
        contactnn.make_network(w, [np.zeros(5), t[1]], **scaling)
    with pytest.raises(ValueError, match="real_type 'float16'"):
        contactnn.make_network(w, t, real_type="float16", **scaling)
    with pytest.raises(ValueError):
        contactnn.make_network(w, t, **dict(scaling, input_min=np.zeros(3)))
    network = contactnn.make_network(w, t, **scaling)
    with pytest.raises(ValueError, match=r"features: shape \(4, 7\), expected \(n, 8\)"):
        network.evaluate(np.zeros((4, 7)))
    with pytest.raises(contactnn.IoError) as e:
        network.write(str(tmp_path / "no-such-directory" / "net.h5"))
    assert isinstance(e.value, OSError) and e.value.exit_code == 4
    with pytest.raises(contactnn.FormatError) as e:
        contactnn.read_network(os.path.join(os.environ["CONTACTNN_SOURCE_DIR"], "data", "examples", "raw-bilinear.csv"))
    assert e.value.exit_code == 3
