"""Direction following in unknown buildings: laser and instruction layers, LSTM network,
training, evaluation, node.
"""
