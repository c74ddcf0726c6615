"""Bullet's own report sections (beside the generic ones every engine gets)."""
