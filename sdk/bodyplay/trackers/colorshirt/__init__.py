"""bodyplay.trackers.colorshirt"""
