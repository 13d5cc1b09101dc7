"""Command line of scripts/mix_semnav_models: θ = (1 − α) θ_base + α θ_tuned for every layer
(network.interpolate_weights, WiSE-FT), saved with a card of the command and both inputs."""
import argparse
import hashlib
import json
import sys
from pathlib import Path


def argument_parser(description=None):
    """The options of mix_semnav_models."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--base", type=Path, required=True, help="the model fine-tuning began at")
    parser.add_argument("--tuned", type=Path, required=True, help="the fine-tuned model")
    parser.add_argument("--alpha", type=float, default=0.5,
                        help="weight of the fine-tuned model, in [0, 1] (default 0.5)")
    parser.add_argument("--out", type=Path, required=True, help="the mixed .keras model")
    return parser


def sha256_of(path):
    """SHA-256 of a file's bytes, hex."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def mix_models(base_path, tuned_path, alpha):
    """The tuned model with every layer's weights mixed with the base's; ValueError when the
    two do not have the same layers."""
    from semantic_nav.network import interpolate_weights, load_network
    base, tuned = load_network(base_path), load_network(tuned_path)
    for name, weights in interpolate_weights(base, tuned, alpha).items():
        tuned.get_layer(name).set_weights(weights)
    return tuned


def model_card(command, alpha, base, tuned):
    """The card beside the mixed model: command, α and both inputs with their SHA-256."""
    return {"command": command, "alpha": alpha,
            "base": {"path": str(base), "sha256": sha256_of(base)},
            "tuned": {"path": str(tuned), "sha256": sha256_of(tuned)}}


def main(argv=None, description=None):
    """Parse, mix, save the model and its card -> exit status 0 (bad inputs exit naming
    them)."""
    args = argument_parser(description).parse_args(argv)
    for path in (args.base, args.tuned):
        if not path.is_file():
            sys.exit(f"mix_semnav_models: no model file {path}")
    try:
        mixed = mix_models(args.base, args.tuned, args.alpha)
    except ValueError as error:
        sys.exit(f"mix_semnav_models: {args.base} and {args.tuned}: {error}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    mixed.save(args.out)
    card = model_card(" ".join(sys.argv if argv is None else ["mix_semnav_models", *argv]),
                      args.alpha, args.base, args.tuned)
    args.out.with_suffix(".json").write_text(json.dumps(card, indent=1))
    print(f"mix_semnav_models: {args.out} = {1 - args.alpha:g} x {args.base} "
          f"+ {args.alpha:g} x {args.tuned}")
    return 0
