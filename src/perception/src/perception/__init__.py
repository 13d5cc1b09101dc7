"""Visual and verbal perception of the social robot: detectors, pose, localisation, activity,
speech, sentiment, requests.
"""
