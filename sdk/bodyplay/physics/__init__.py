"""bodyplay.physics"""
