"""Training run of the semantic_nav network (thesis 002 §4.1) on demonstration records.

`Trainer(TrainerConfig(...), report=print).run()` does what `scripts/train_semnav` does: each
epoch, every training record subsampled to the control rate with a random phase and paired with a
random sentence of its class (§3.4), plus a few Z_w batches of phrase-set sentences; then the
validation function of §4.1.2 on the validation records ([correct, destination]) and the monitors
of §4.1.3, which save the lowest-loss and the best-validation model. Beyond the seed, a
closed-loop monitor (`closed_loop_plan`) drives validation-floor episodes after each epoch and
keeps the model that reached the most goals. A KeyboardInterrupt saves the current model.

Everything of a run goes to `work_dir`: config.json (config and arguments), history.json,
current.keras, lowest_loss.keras, best_validation.keras, best_closed_loop.keras, training.png,
and checkpoint/, rewritten after every epoch (weights, both optimizers' state, the monitors, the
history and the random generators' state): with `resume` an interrupted run goes on from its
last finished epoch and ends as the uninterrupted run would.
Progress goes to the `report` callback as lines, each stage with its ETA. Random numbers are drawn
in a fixed order from `seed` (Keras's global seed and one numpy generator), so a run is repeated
exactly by the same configuration.
"""
import dataclasses
import json
import shutil
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from semnav_learning.training import TrainingConfig, ValidationThresholds

SELECTIONS = ("best_validation", "lowest_loss", "best_closed_loop", "current")
INTERRUPTED_EXIT = 130   # exit status of an interrupted run (128 + SIGINT)


class TrainingError(ValueError):
    """A run that cannot start: a bad setting, missing records, an unusable plan."""


@dataclass
class TrainerConfig:
    """One training run (the command line of scripts/train_semnav as data); None: the default
    of `training` / `network`."""

    dataset: list = field(default_factory=list)   # dataset directories (build_semnav_dataset)
    work_dir: Path = Path("build/semnav_train/run")  # everything of the run goes here
    laser_config: Path = None     # config/semnav_laser.yaml (laser models, canonical scan)
    phrases: Path = None          # config/semnav_phrases.yaml
    world_template: Path = None   # sim2d world of the closed-loop episodes (Penguin + UTM-30LX)
    laser: str = "utm30lx"        # laser model of the records
    train_split: str = "train"
    validation_split: str = "validation"
    dagger_records: list = field(default_factory=list)  # DAgger record files (control rate)
    init: Path = None             # continue from this .keras model
    epochs: int = None
    learning_rate: float = None
    stop_weight: float = None     # loss weight of zero-label steps
    mirror: float = None          # share of training sequences mirrored each epoch [0, 1]
    word_noise: float = None      # std of the noise on training word vectors
    retrain_classifier: int = None  # with init: Z_w-only batches, then save and stop
    turn_weight: float = None     # loss weight of steps where the expert turns
    stop_head: bool = False       # add (or keep) the stop output
    stop_loss_weight: float = None
    decision_head: bool = False   # add (or keep) the distance-to-decision output
    decision_horizon: float = None  # [m]
    decision_loss_weight: float = None
    count_input: bool = False     # corners counted so far as an input of LSTM_fused
    count_head: bool = False      # learned counting: no count input (an init's is dropped), the
    #                               counting mode as an input and the count as an output
    follower_config: Path = None  # follower YAML of the closed-loop monitor (None: default)
    balance_classes: int = 1      # rare classes' records repeated up to this many times
    batch_size: int = None
    scan_units: int = None
    fused_units: int = None
    seed: int = 0
    threads: int = 1              # torch CPU threads
    closed_loop_plan: list = None  # eval_semnav plan files on validation floors
    select: str = "best_validation"  # model copied to `out`: one of SELECTIONS
    out: Path = None              # copy the selected model here (.keras) with a model card
    cache: Path = None            # preprocessed-scan cache directory (None: no cache)
    words: str = None             # GloVe text file or cache directory (None: default cache)
    door_width: float = 0.0       # close doorways narrower than this in record scans [m]
    command: str = ""             # the command line, for the model card
    resume: bool = False          # go on from work_dir/checkpoint (same configuration) if there
    training: TrainingConfig = field(default_factory=TrainingConfig)  # defaults under the
                                  # fields above, as `network`
    network: object = None        # semantic_nav.network.NetworkConfig (None: its defaults)


TRAINING_OVERRIDES = ("epochs", "stop_weight", "turn_weight", "batch_size", "decision_horizon")
NETWORK_OVERRIDES = ("scan_units", "fused_units", "learning_rate", "stop_loss_weight",
                     "decision_loss_weight")


def format_duration(seconds):
    """12.3 s, 4 min 05 s, 2 h 07 min."""
    if seconds < 60:
        return f"{seconds:.1f} s"
    minutes, secs = divmod(int(round(seconds)), 60)
    if minutes < 60:
        return f"{minutes} min {secs:02d} s"
    return f"{minutes // 60} h {minutes % 60:02d} min"


class StageProgress:
    """Progress lines of one stage: steps done, elapsed time and ETA, about every tenth of it."""

    def __init__(self, stage, total, unit, report, parts=10, clock=time.perf_counter):
        self.stage, self.total, self.unit, self.report = stage, total, unit, report
        self.clock, self.began, self.done = clock, clock(), 0
        self.every = max(1, total // parts)

    def step(self, note=""):
        """One step done; a line when a tenth of the stage (or all of it) is done."""
        self.done += 1
        if self.done % self.every and self.done != self.total:
            return
        elapsed = self.clock() - self.began
        eta = elapsed / self.done * (self.total - self.done)
        self.report(f"{self.stage}: {self.done}/{self.total} {self.unit}, "
                    f"{format_duration(elapsed)} elapsed, ETA {format_duration(eta)}"
                    + (f", {note}" if note else ""))


def balance_classes(episodes, max_repeat):
    """Each class's episodes repeated round(commonest count / its count) times, at most
    max_repeat (1: unchanged)."""
    counts = Counter(e.label for e in episodes)
    if max_repeat <= 1 or not counts:
        return episodes
    most = max(counts.values())
    return [e for e in episodes
            for _ in range(min(max_repeat, max(1, round(most / counts[e.label]))))]


def validate(model, batches, thresholds, rate):
    """§4.1.2 over the fixed validation batches -> ([correct, destination], Z_w accuracy)."""
    from semnav_learning.training import batch_rows, validation_value
    pairs, hits, total = [], 0, 0
    for inputs, targets, weights in batches:
        out = model.predict_on_batch(inputs)
        pairs += [(reference, output) for _, reference, output in
                  batch_rows(targets, out, weights)]
        predicted = np.argmax(np.asarray(out["instruction_class"]), axis=1)
        hits += int((predicted == targets["instruction_class"]).sum())
        total += len(predicted)
    return validation_value(pairs, thresholds, rate), hits / max(total, 1)


def plot_history(history, path, initial=None):
    """training.png: the loss monitor, the validation monitor and (if run) the closed loop."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    epochs = [h["epoch"] for h in history]
    closed = [h.get("closed_loop") for h in history]
    panels = 3 if any(c is not None for c in closed) else 2
    fig, axes = plt.subplots(1, panels, figsize=(5 * panels, 3.6))
    ax1, ax2 = axes[:2]
    ax1.semilogy(epochs, [h["velocity_loss"] for h in history], label="velocity MSE")
    ax1.semilogy(epochs, [h["class_loss"] for h in history], label="Z_w cross-entropy")
    ax1.set_xlabel("epoch"), ax1.set_title("loss monitor"), ax1.legend()
    ax2.plot(epochs, [h["valid"][1] for h in history], "g-", label="destination")
    ax2.set_xlabel("epoch"), ax2.set_ylabel("destinations reached")
    twin = ax2.twinx()
    twin.plot(epochs, [h["valid"][0] for h in history], "b:", label="correct")
    twin.set_ylabel("correct outputs")
    ax2.set_title("validation monitor [correct, destination]")
    if panels == 3:
        if initial:
            epochs, closed = [0, *epochs], [initial["closed_loop"], *closed]
        axes[2].plot(epochs, closed, "k.-")
        axes[2].set_xlabel("epoch"), axes[2].set_ylabel("goals reached")
        axes[2].set_title("closed-loop monitor (validation floors)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def selected_entry(history, select, closed_loop_init=None):
    """The history entry the `select` monitor chose (a closed-loop tie keeps the init model)."""
    chosen = {"lowest_loss": lambda h: h["velocity_loss"],
              "best_validation": lambda h: (-h["valid"][1], -h["valid"][0]),
              "best_closed_loop": lambda h: -h["closed_loop"],
              "current": lambda h: -h["epoch"]}[select]
    candidates = history
    if select == "best_closed_loop" and closed_loop_init:
        candidates = [closed_loop_init, *history]
    return min(candidates, key=chosen) if candidates else None


def config_record(config):
    """The run's settings, JSON-friendly (paths as strings), without the nested defaults."""
    skip = {"training", "network", "command"}
    return {f.name: str(v) if isinstance(v, Path) else v
            for f in dataclasses.fields(config) if f.name not in skip
            for v in [getattr(config, f.name)]}


class Trainer:
    """One training run; `run()` calls the stages in their fixed order."""

    def __init__(self, config, report=print):
        self.config, self.report = config, report
        self.training = self.thresholds = self.net = None
        self.words = self.sets = self.rng = None
        self.history, self.summary, self.record = [], None, None

    def check(self):
        """Settings that cannot work together -> TrainingError."""
        c = self.config
        if c.select not in SELECTIONS:
            raise TrainingError(f"select must be one of {', '.join(SELECTIONS)}, got {c.select}")
        if c.select == "best_closed_loop" and not c.closed_loop_plan:
            raise TrainingError("--select best_closed_loop needs --closed-loop-plan")
        if c.retrain_classifier is not None and (c.init is None or c.retrain_classifier < 1):
            raise TrainingError("--retrain-classifier needs --init MODEL and a number of "
                                "batches >= 1")

    def configure(self):
        """TrainingConfig, ValidationThresholds and NetworkConfig with the overrides and the
        datasets' record rate (summary.yaml of build_semnav_dataset)."""
        from semantic_nav.network import NetworkConfig
        from semnav_learning.training import dataset_record_rate
        c = self.config
        config = dataclasses.replace(c.training)
        net_config = dataclasses.replace(c.network) if c.network else NetworkConfig()
        thresholds = ValidationThresholds()
        for target, names in ((config, TRAINING_OVERRIDES), (net_config, NETWORK_OVERRIDES)):
            for name in names:
                if getattr(c, name) is not None:
                    setattr(target, name, getattr(c, name))
        if c.mirror is not None:
            if not 0.0 <= c.mirror <= 1.0:
                raise TrainingError(f"--mirror must be a share between 0 and 1, got {c.mirror}")
            config.mirror_probability = c.mirror
        if c.word_noise is not None:
            if c.word_noise < 0:
                raise TrainingError("--word-noise must be a standard deviation >= 0, got "
                                    f"{c.word_noise}")
            config.word_noise = c.word_noise
        self.training, self.thresholds, self.net = config, thresholds, net_config
        if c.retrain_classifier is not None:
            return                                      # no records are read
        rates = {dataset_record_rate(d, config.record_rate) for d in c.dataset}
        if len(rates) > 1:
            raise TrainingError("--dataset: the datasets were recorded at different rates "
                                f"{sorted(rates)} Hz")
        if rates:
            config.record_rate = rates.pop()

    def enable_heads(self, initial):
        """The optional outputs (and their targets) asked for or that the init model has."""
        from semantic_nav.network import has_count_input, has_head
        c, config, net_config = self.config, self.training, self.net
        for head in ("stop", "decision"):
            if getattr(c, f"{head}_head") or (initial is not None and has_head(initial, head)):
                setattr(net_config, f"{head}_head", True)
                setattr(config, f"{head}_targets", True)
        if c.count_head:        # learned counting: the network counts, no counter feeds it
            net_config.count_head = net_config.counting_input = True
            config.count_targets = config.counting_inputs = True
        elif c.count_input or (initial is not None and has_count_input(initial)):
            net_config.count_input = config.count_inputs = True
        if initial is not None and has_head(initial, "count"):
            net_config.count_head = net_config.counting_input = True
            config.count_targets = config.counting_inputs = True

    def load_data(self):
        """-> (training episodes, validation episodes, training files, validation files)."""
        from semantic_nav.doorways import DoorConfig
        from semantic_nav.laser_layer import load_laser_config
        from semnav_learning.training import load_episodes, split_record_files
        c, config = self.config, self.training
        models, canonical, preprocess = load_laser_config(c.laser_config)
        laser = models[c.laser]
        train_files = split_record_files(c.dataset, c.train_split)
        valid_files = split_record_files(c.dataset, c.validation_split)
        if not train_files or not valid_files:
            raise TrainingError(f"no records in {c.train_split} or {c.validation_split} of "
                                f"{', '.join(map(str, c.dataset))}: run "
                                "scripts/build_semnav_dataset")
        doors = DoorConfig(width=c.door_width)
        train = load_episodes(train_files, laser, canonical, preprocess, c.cache,
                              config.record_rate, doors=doors)
        train += load_episodes(c.dagger_records, laser, canonical, preprocess, c.cache,
                               config.control_rate, doors=doors)
        train_files += [str(f) for f in c.dagger_records]
        train = balance_classes(train, c.balance_classes)
        valid = load_episodes(valid_files, laser, canonical, preprocess, c.cache,
                              config.record_rate, doors=doors)
        return train, valid, [str(f) for f in train_files], [str(f) for f in valid_files]

    def closed_loop_plan(self, train_files):
        """The plans' episodes (of every file, in order); TrainingError if a file is not a plan,
        a floor is missing or a floor is one the network trains on."""
        from semnav_learning.evaluation import load_plan
        plans = self.config.closed_loop_plan
        try:
            specs = [spec for path in plans for spec in load_plan(path)]
        except (OSError, ValueError) as error:
            raise TrainingError(f"--closed-loop-plan: {error}") from error
        where = f"--closed-loop-plan {' '.join(str(p) for p in plans)}"
        if not specs:
            raise TrainingError(f"{where}: no episodes")
        floors = sorted({s.floor for s in specs})
        missing = [f for f in floors if not Path(f).is_file()]
        if missing:
            raise TrainingError(f"{where}: missing floor(s) {', '.join(missing)}")
        trained = {Path(f).stem for f in train_files} & {Path(f).stem for f in floors}
        if trained:
            raise TrainingError(f"{where}: floor(s) {', '.join(sorted(trained))} are training "
                                "floors")
        return specs

    def closed_loop_success(self, model, specs):
        """Drive the episodes with the current weights -> (goals reached, {class: reached})."""
        from semnav_learning.evaluation import PolicySpec, evaluate, success_table
        path = self.config.work_dir / "current.keras"
        model.save(path)
        # spawned workers, one per training thread (idle meanwhile): a pool forked from the
        # training process (torch threads running) hung
        outcomes = evaluate(specs, self.config.world_template,
                            PolicySpec(model_path=str(path), config=self.config.follower_config
                                       and str(self.config.follower_config)),
                            workers=self.config.threads,
                            start_method="spawn")
        rows, total = success_table(outcomes)
        return total[2], {label: successes for label, _, successes, _ in rows}

    def closed_loop_before(self, model, specs):
        """The init model on the closed-loop episodes ("epoch 0"): fine-tuning keeps it unless an
        epoch reaches more goals. -> its history-like entry."""
        reached, per_class = self.closed_loop_success(model, specs)
        work = self.config.work_dir
        shutil.copyfile(work / "current.keras", work / "best_closed_loop.keras")
        self.report(f"closed loop before training (--init): {reached}/{len(specs)} goals "
                    f"{list(per_class.values())}")
        return {"epoch": 0, "closed_loop": reached, "closed_loop_classes": per_class}

    def build_model(self, initial):
        """The init model with the asked heads and inputs beside [Z_w, Z_s], or a new network."""
        from semantic_nav.network import build_network, rebuild_fused_inputs
        if initial is None:
            return build_network(self.net)
        return rebuild_fused_inputs(initial, self.net)

    def warm_up_classifier(self, classifier):
        """LSTM_w first, on phrase-set sentences alone (cheap: no scans), so Z_w is meaningful
        when the fused stage starts learning."""
        from semnav_learning.training import class_batch
        config = self.training
        progress = StageProgress("Z_w warm-up", config.class_warmup_batches, "batches",
                                 self.report)
        for _ in range(config.class_warmup_batches):
            loss = classifier.train_on_batch(*class_batch(self.sets, self.words, self.rng,
                                                          config.class_batch_size))
            progress.step(f"loss {float(loss):.4f}")

    def train_epoch(self, epoch, model, classifier, train_eps):
        """One epoch's batches in a random order and its Z_w batches -> (velocity loss, class
        loss, {head: mean loss} of the decision and count heads the model has)."""
        from semnav_learning.training import batch_arrays, batch_chunks, class_batch
        config, rng = self.training, self.rng
        chunks = batch_chunks(train_eps, self.sets, self.words, rng, config)
        order = rng.permutation(len(chunks))
        losses, head_losses = [], {}
        progress = StageProgress(f"Epoch {epoch}/{config.epochs}", len(order), "batches",
                                 self.report)
        for index in order:
            logs = model.train_on_batch(*batch_arrays(chunks[index], self.words.dim, config),
                                        return_dict=True)
            losses.append((logs["velocity_loss"], logs["instruction_class_loss"]))
            for head in ("decision", "count"):
                if f"{head}_loss" in logs:
                    head_losses.setdefault(head, []).append(logs[f"{head}_loss"])
            progress.step(f"loss {logs['velocity_loss']:.5f}")
        for _ in range(config.class_batches):
            classifier.train_on_batch(*class_batch(self.sets, self.words, rng,
                                                   config.class_batch_size))
        velocity_loss, class_loss = (float(np.mean(x)) for x in zip(*losses))
        return velocity_loss, class_loss, {head: float(np.mean(values))
                                           for head, values in head_losses.items()}

    def train(self, model, classifier, data, initial=None, checkpoint=None):
        """The epoch loop with the monitors; appends one entry per epoch to self.history.
        `initial`: the init model's closed-loop entry (closed_loop_before); `checkpoint`: the
        state of a checkpoint restored into the model (restore_checkpoint), to go on from."""
        from semnav_learning.training import Monitor
        config, work = self.training, self.config.work_dir
        train_eps, valid_batches, closed_specs = data
        loss_monitor, valid_monitor = Monitor("loss"), Monitor("validation")
        closed_monitor = Monitor("closed_loop")
        monitors = {"loss": loss_monitor, "valid": valid_monitor, "closed": closed_monitor}
        if initial:
            closed_monitor.update(initial["closed_loop"])
        first = 1
        if checkpoint:
            for name, monitor in monitors.items():
                monitor.best = checkpoint["monitors"][name]
            first = checkpoint["epoch"] + 1
        for epoch in range(first, config.epochs + 1):
            began = time.perf_counter()
            velocity_loss, class_loss, head_losses = self.train_epoch(
                epoch, model, classifier, train_eps)
            valid, valid_accuracy = validate(model, valid_batches, self.thresholds,
                                             config.control_rate)
            if loss_monitor.update(velocity_loss):
                model.save(work / "lowest_loss.keras")
            if valid_monitor.update(valid):
                model.save(work / "best_validation.keras")
            entry = {"epoch": epoch, "velocity_loss": velocity_loss, "class_loss": class_loss,
                     "valid": valid, "valid_class_accuracy": valid_accuracy,
                     "loss_monitor": loss_monitor.best, "valid_monitor": valid_monitor.best}
            entry.update({f"{head}_loss": loss for head, loss in head_losses.items()})
            closed = ""
            if closed_specs:
                reached, per_class = self.closed_loop_success(model, closed_specs)
                if closed_monitor.update(reached):
                    shutil.copyfile(work / "current.keras", work / "best_closed_loop.keras")
                entry.update(closed_loop=reached, closed_loop_classes=per_class,
                             closed_loop_monitor=closed_monitor.best)
                closed = (f"\nclosed loop: {reached}/{len(closed_specs)} goals "
                          f"{list(per_class.values())}, closed-loop monitor: "
                          f"{closed_monitor.best}")
            self.history.append({**entry, "seconds": round(time.perf_counter() - began, 1)})
            self.save_checkpoint(model, classifier, epoch, monitors, initial)
            remaining = np.mean([h["seconds"] for h in self.history]) * (config.epochs - epoch)
            self.report(f"Epoch {epoch}/{config.epochs} - {self.history[-1]['seconds']}s, "
                        f"training ETA {format_duration(remaining)}\n"
                        f"loss: {velocity_loss:.6f} , valid: {valid}\n"
                        f"loss monitor: {loss_monitor.best:.6f} , valid monitor: "
                        f"{valid_monitor.best}" + closed)

    def checkpoint_key(self):
        """What a checkpoint must have been made with: the run's record (config.json)."""
        return json.dumps(self.record, sort_keys=True, default=str)

    def save_checkpoint(self, model, classifier, epoch, monitors, initial):
        """work_dir/checkpoint after `epoch`: weights, the optimizers' variables, the torch and
        numpy generators, monitors and history; written beside and renamed into place, so an
        interrupt leaves the previous checkpoint whole."""
        import torch
        work = self.config.work_dir
        temporary, final = work / "checkpoint.partial", work / "checkpoint"
        shutil.rmtree(temporary, ignore_errors=True)
        temporary.mkdir()
        arrays = {f"weight_{k}": w for k, w in enumerate(model.get_weights())}
        for name, net in (("model", model), ("classifier", classifier)):
            arrays.update({f"{name}_optimizer_{k}": np.asarray(v)
                           for k, v in enumerate(net.optimizer.variables)})
        arrays["torch_rng"] = torch.get_rng_state().numpy()
        np.savez(temporary / "arrays.npz", **arrays)
        state = {"epoch": epoch, "key": self.checkpoint_key(), "history": self.history,
                 "initial": initial, "rng": self.rng.bit_generator.state,
                 "monitors": {name: m.best for name, m in monitors.items()}}
        (temporary / "state.json").write_text(json.dumps(state, default=float))
        shutil.rmtree(final, ignore_errors=True)
        temporary.rename(final)

    def checkpoint_state(self):
        """The state of work_dir/checkpoint, or None without one; TrainingError if it was made
        with another configuration."""
        path = self.config.work_dir / "checkpoint" / "state.json"
        if not path.is_file():
            return None
        state = json.loads(path.read_text())
        if state["key"] != self.checkpoint_key():
            raise TrainingError(f"{path.parent} was made with another configuration than this "
                                "run's (see config.json there); delete it or run without resume")
        return state

    def restore_checkpoint(self, model, classifier, state):
        """Weights, optimizer variables, generators and history of the checkpoint."""
        import torch
        arrays = np.load(self.config.work_dir / "checkpoint" / "arrays.npz")
        model.set_weights([arrays[f"weight_{k}"] for k in range(len(model.get_weights()))])
        for name, net in (("model", model), ("classifier", classifier)):
            saved = sorted((int(key.rsplit("_", 1)[1]), key) for key in arrays.files
                           if key.startswith(f"{name}_optimizer_"))
            if saved:
                net.optimizer.build(net.trainable_variables)
                for variable, (_, key) in zip(net.optimizer.variables, saved, strict=True):
                    variable.assign(arrays[key])
        torch.set_rng_state(torch.from_numpy(arrays["torch_rng"]))
        self.rng.bit_generator.state = state["rng"]
        self.history = list(state["history"])

    def retrain_classifier(self, model):
        """Z_w-only batches on the init model, then its card. Z_w is the only input LSTM_fused
        takes from the words, so control is unchanged wherever Z_w stays the same one-hot class;
        the clean training-phrasing accuracy reported at the end checks that. A phrasing monitor
        (§4.1.3's monitors, on the phrase sets' validation phrasings, never the held-out ones)
        keeps the best LSTM_w seen. -> the summary written to history.json."""
        from semantic_nav.network import build_classifier
        from semnav_learning.training import Monitor, class_batch, class_hits_and_loss
        c, config, rng, sets, words = self.config, self.training, self.rng, self.sets, self.words
        batches = c.retrain_classifier
        classifier = build_classifier(model)
        began, losses, checks = time.perf_counter(), [], []
        valid_rng = np.random.default_rng(config.class_monitor_seed)
        valid_inputs, valid_labels = class_batch(sets, words, valid_rng, config.class_monitor_size,
                                                 split="validation")
        monitor, kept = Monitor("phrasing"), None

        def check(batch_number):
            nonlocal kept
            hits, loss = class_hits_and_loss(classifier.predict_on_batch(valid_inputs),
                                             valid_labels)
            checks.append({"batches": batch_number, "validation_hits": hits,
                           "validation_loss": loss})
            if monitor.update((hits, loss)):
                kept = (batch_number, classifier.get_weights())
            return hits

        check(0)
        progress = StageProgress("Z_w", batches, "batches", self.report)
        for batch_number in range(1, batches + 1):
            batch = class_batch(sets, words, rng, config.class_batch_size, noise=config.word_noise)
            losses.append(float(classifier.train_on_batch(*batch)))
            note = f"loss {losses[-1]:.4f}"
            if batch_number % config.class_monitor_every == 0 or batch_number == batches:
                hits = check(batch_number)
                note += f", valid {hits}/{config.class_monitor_size}"
            progress.step(note)
        classifier.set_weights(kept[1])
        self.report(f"phrasing monitor kept batch {kept[0]}: {monitor.best[0]}/"
                    f"{config.class_monitor_size} validation-phrasing sentences right")
        # clean training phrasings, as the fused stage learnt them: Z_w must stay one-hot there
        inputs, labels = class_batch(sets, words, rng, 1000)
        hits, train_loss = class_hits_and_loss(classifier.predict_on_batch(inputs), labels)
        self.report(f"Z_w on 1000 training-phrasing sentences: {hits / 10:.1f} % correct, mean "
                    f"cross-entropy {train_loss:.2e}")
        model.save(c.work_dir / "current.keras")
        summary = {"retrain_classifier": batches, "word_noise": config.word_noise,
                   "loss_every_50": losses[::50] + losses[-1:],
                   "phrasing_monitor": checks, "kept_batch": kept[0],
                   "train_phrasing_accuracy": hits / 1000, "train_phrasing_loss": train_loss,
                   "seconds": round(time.perf_counter() - began, 1)}
        (c.work_dir / "history.json").write_text(json.dumps(summary, indent=1))
        if c.out:
            c.out.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(c.work_dir / "current.keras", c.out)
            card = {"command": c.command, **summary, "args": config_record(c)}
            c.out.with_suffix(".json").write_text(json.dumps(card, indent=1, default=str))
            self.report(f"model -> {c.out}")
        self.summary = summary
        return summary

    def write_model_card(self):
        """<out>.json beside the model: how it was trained and its training figures."""
        c, summary = self.config, self.summary
        history = summary["history"]
        best = selected_entry(history, c.select, summary.get("closed_loop_init"))
        card = {"command": c.command, "selected": c.select, "selected_epoch": best,
                "epochs_run": len(history), "training_seconds": summary["seconds"],
                "last_epoch": history[-1] if history else None, **self.record}
        c.out.with_suffix(".json").write_text(json.dumps(card, indent=1, default=str))

    def finish(self, model, interrupted, initial, began):
        """current.keras, history.json, training.png and the selected model with its card."""
        c = self.config
        model.save(c.work_dir / "current.keras")
        self.summary = {"history": self.history, "interrupted": interrupted,
                        "closed_loop_init": initial,
                        "seconds": round(time.perf_counter() - began, 1)}
        (c.work_dir / "history.json").write_text(json.dumps(self.summary, indent=1))
        if self.history:
            plot_history(self.history, c.work_dir / "training.png", initial)
        if c.out:
            selected = c.work_dir / f"{c.select}.keras"
            if interrupted and not selected.is_file():   # stopped before any epoch chose one
                self.report(f"interrupted before a {c.select} model: {c.out} not written "
                            f"(current.keras is in {c.work_dir})")
                return
            c.out.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(selected, c.out)
            self.write_model_card()
            self.report(f"{c.select} model -> {c.out}")

    def run(self):
        """The whole run -> its summary (history.json's content; "interrupted" true after a
        KeyboardInterrupt, the current model saved)."""
        self.check()
        import keras
        import torch
        from semantic_nav.network import add_heads, build_classifier, load_network
        from semantic_nav.word_vectors import load_word_vectors
        from semnav_learning.phrase_sets import load_phrase_sets
        from semnav_learning.training import make_batches
        c = self.config
        torch.set_num_threads(c.threads)
        keras.utils.set_random_seed(c.seed)
        self.rng = np.random.default_rng(c.seed)
        self.configure()
        initial = load_network(str(c.init)) if c.init else None
        self.enable_heads(initial)
        c.work_dir.mkdir(parents=True, exist_ok=True)
        self.words = load_word_vectors(c.words)
        self.sets = load_phrase_sets(c.phrases)
        if c.retrain_classifier is not None:
            return self.retrain_classifier(add_heads(initial, self.net))
        config = self.training
        train_eps, valid_eps, train_files, valid_files = self.load_data()
        closed_specs = self.closed_loop_plan(train_files) if c.closed_loop_plan else []
        self.record = {"args": config_record(c),
                       "training": dataclasses.asdict(config),
                       "network": dataclasses.asdict(self.net),
                       "validation": dataclasses.asdict(self.thresholds),
                       "train_files": train_files, "validation_files": valid_files,
                       "train_records": len(train_eps), "validation_records": len(valid_eps),
                       "closed_loop_episodes": len(closed_specs),
                       "dagger_records": [str(p) for p in c.dagger_records]}
        (c.work_dir / "config.json").write_text(json.dumps(self.record, indent=1, default=str))
        model = self.build_model(initial)
        classifier = build_classifier(model)
        valid_rng = np.random.default_rng(c.seed + 1)  # fixed pairing for every epoch
        valid_batches = make_batches(valid_eps, self.sets, self.words, valid_rng, config,
                                     phases=[0] * len(valid_eps))
        checkpoint = self.checkpoint_state() if c.resume else None
        if not c.init and checkpoint is None:
            self.warm_up_classifier(classifier)
        self.report(f"train: {len(train_eps)} records ({sum(len(e.commands) for e in train_eps)} "
                    f"samples at {config.record_rate:g} Hz) -> {config.control_rate:g} Hz; "
                    f"validation: {len(valid_eps)} records; work directory {c.work_dir}")
        began = time.perf_counter()
        interrupted, initial = False, None
        try:
            if checkpoint is not None:
                self.restore_checkpoint(model, classifier, checkpoint)
                initial = checkpoint["initial"]
                self.report(f"resuming after epoch {checkpoint['epoch']}/{config.epochs} from "
                            f"{c.work_dir / 'checkpoint'}")
            elif closed_specs and c.init:
                initial = self.closed_loop_before(model, closed_specs)
            self.train(model, classifier, (train_eps, valid_batches, closed_specs), initial,
                       checkpoint)
        except KeyboardInterrupt:
            interrupted = True
            self.report("interrupted: saving the current model")
        self.finish(model, interrupted, initial, began)
        return self.summary
